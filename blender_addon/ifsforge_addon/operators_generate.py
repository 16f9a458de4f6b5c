"""Generate and Regenerate. Invoked from the UI they run modally: the work runs on a thread,
the window manager shows its progress and Esc cancels; called from a script (execute) they
run in place. Either way the result is one undo step, and errors become reports."""
import traceback

import bpy
from bpy.props import BoolProperty, PointerProperty, StringProperty

import ifsforge

from . import (generate_image, generate_instances, generate_mesh, generate_palette,  # noqa: F401  (they register)
               generate_terrain, generate_volume)
from . import generators, presets, state
from .jobs import Job
from .properties import IFSFORGE_PG_settings, restore, snapshot


def report_error(operator, error):
    """One line in the UI for any failure; a traceback on the console only for bugs."""
    if isinstance(error, ifsforge.Cancelled):
        operator.report({'WARNING'}, "Cancelled")
    elif isinstance(error, (ifsforge.Error, OSError, ValueError, MemoryError)):
        operator.report({'ERROR'}, str(error))
    else:
        traceback.print_exception(type(error), error, error.__traceback__)
        operator.report({'ERROR'}, f"{type(error).__name__}: {error}")


class Plan:
    """What one run makes: from which values, into which datablock (by name, resolved again
    when the work is done, since the UI keeps running meanwhile)."""

    def __init__(self, context, generator, owner, system_pg, settings_pg, new):
        self.generator = generator
        self.values = snapshot(system_pg, settings_pg)
        self.new = new
        base = f"{system_pg.name or 'IFS'} {generator.label.lower()}"
        self.name = generators.unique_name(generator, base) if new else owner.name
        system = state.system_of(system_pg)
        settings = generator.resolve(dict(self.values["settings"]))
        path = generators.output_path(context, generator, self.name, self.values | {"settings": settings})
        self.job = Job(lambda progress: generator.work(system, settings, path, progress))

    def finish(self, context):
        """Creates or updates the datablock; returns it."""
        if self.job.error is not None:
            raise self.job.error
        owner = None if self.new else generators.owner_by_name(self.generator, self.name)
        if owner is None and not self.new:
            raise ifsforge.InputError(f"'{self.name}' was deleted while it was being generated")
        own_data(owner)
        owner = self.generator.apply(context, owner, self.job.result, self.name)
        if self.new and isinstance(owner, bpy.types.Object):
            owner.location = context.scene.cursor.location  # where Blender adds objects
        generators.store(owner, self.generator, self.values if self.new else None, self.job.result)
        owner.ifsforge.built_from = generators.digest(self.values)
        return owner


def own_data(owner):
    """A duplicate (Shift+D of a volume, Alt+D of anything) shares its datablock with the
    original: regenerating it first gives it a copy of its own, so the original is untouched."""
    data = getattr(owner, "data", None)
    if data is not None and data.users > 1:
        owner.data = data.copy()


class JobOperator:
    """Mixin: subclasses define plan(context) -> Plan."""
    bl_options = {'REGISTER', 'UNDO'}
    _plan = None
    _timer = None

    def execute(self, context):
        try:
            plan = self.plan(context)
            plan.job.run()
            owner = plan.finish(context)
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        self.report({'INFO'}, f"{owner.name}: {owner.ifsforge.summary}")
        return {'FINISHED'}

    def invoke(self, context, event):
        try:
            self._plan = self.plan(context)
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        self._plan.job.start()
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.05, window=context.window)
        wm.progress_begin(0, 100)
        wm.modal_handler_add(self)
        context.workspace.status_text_set(f"ifsforge: {self._plan.generator.label.lower()} of "
                                          f"'{self._plan.name}'... (Esc to cancel)")
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        job = self._plan.job
        if event.type == 'ESC' and event.value == 'PRESS':
            job.cancel()
            return {'RUNNING_MODAL'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        context.window_manager.progress_update(int(100 * job.fraction))
        if not job.done:
            context.workspace.status_text_set(f"ifsforge: {self._plan.generator.label.lower()} of '{self._plan.name}' "
                                              f"{int(100 * job.fraction)}% (Esc to cancel)")
            return {'RUNNING_MODAL'}
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        try:
            owner = self._plan.finish(context)
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        self.report({'INFO'}, f"{owner.name}: {owner.ifsforge.summary}")
        return {'FINISHED'}


def _generate_operator(kind, description):
    """An IFSFORGE_OT_generate_<kind> class: a new datablock from the edited system (or from the
    sample `sample`), at the 3D cursor. The settings are the operator's own (copied from the
    edited ones on the first run), so F9 "Adjust Last Operation" re-runs it with changed values
    and operator presets (shipped for the samples, user-savable) can set them."""

    def plan(self, context):
        generator = generators.get(kind)
        reason = generator.missing()
        if reason:
            raise ifsforge.Error(reason)
        owner, system_pg, settings_pg = state.target(context)
        if self.sample:  # into the scene's design (never over a selected object's stored system)
            from .operators_design import load_into  # (operators_design imports this module)
            design = context.scene.ifsforge
            owner, system_pg, settings_pg = context.scene, design.system, design.settings
            load_into(context, self, system_pg, ifsforge.load(str(presets.sample("systems", self.sample))),
                      settings_pg)
        if not self.adjusted:  # first run: start from the edited settings
            restore({**snapshot(system_pg, settings_pg), "record": None}, None, self.settings)
            self.adjusted = True
        return Plan(context, generator, owner, system_pg, self.settings, new=True)

    @classmethod
    def poll(cls, context):
        reason = generators.get(kind).missing()
        if reason:
            cls.poll_message_set(reason)
        return not reason

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "sample")
        layout.prop(self.settings, "seed")
        generators.get(kind).draw(layout, self.settings, state.analyse(state.target(context)[1]).system)

    name = kind.lower()
    return type(f"IFSFORGE_OT_generate_{name}", (JobOperator, bpy.types.Operator), {
        "bl_idname": f"ifsforge.generate_{name}", "bl_label": f"Generate {generators.get(kind).label}",
        "bl_description": description, "bl_options": {'REGISTER', 'UNDO', 'PRESET'},
        "plan": plan, "poll": poll, "draw": draw,
        "__annotations__": {
            "settings": PointerProperty(type=IFSFORGE_PG_settings, options={'SKIP_SAVE'}),
            "sample": StringProperty(name="Sample", options={'SKIP_SAVE'},
                                     description="A sample system file to generate from (empty: the edited system)"),
            "adjusted": BoolProperty(options={'HIDDEN', 'SKIP_SAVE'}),
        }})


class IFSFORGE_OT_regenerate(JobOperator, bpy.types.Operator):
    """Rebuild a generated object (or image) from the system and settings stored on it"""
    bl_idname = "ifsforge.regenerate"
    bl_label = "Regenerate"
    image: bpy.props.StringProperty(name="Image", description="A generated image (empty: the active object)")

    def owner(self, context):
        if self.image:
            return bpy.data.images.get(self.image)
        return context.active_object

    def plan(self, context):
        owner = self.owner(context)
        if not state.generated(owner):
            raise ifsforge.InputError("nothing to regenerate: select an object (or name an image) made by ifsforge")
        generator = generators.get(owner.ifsforge.kind)
        reason = generator.missing()
        if reason:
            raise ifsforge.Error(reason)
        return Plan(context, generator, owner, owner.ifsforge.system, owner.ifsforge.settings, new=False)


def regenerate_now(context, owner, source=None):
    """Synchronous regeneration (frame changes, renders, missing files), from the owner's stored
    values or from `source` (its evaluated copy's ifsforge group). Returns an error message or ''."""
    source = source or owner.ifsforge
    try:
        plan = Plan(context, generators.get(owner.ifsforge.kind), owner, source.system, source.settings, new=False)
        plan.job.run()
        plan.finish(context)
    except Exception as error:
        return f"{owner.name}: {error}"
    return ""


GENERATE_KINDS = (
    ('IMAGE', "Render the system to a PNG (any chapter-5 algorithm) and load it as an image"),
    ('VOLUME', "Write an OpenVDB volume (density and colour grids) and add a Volume object with a "
               "Principled Volume material"),
    ('INSTANCES', "Add a collection of instanced CSG primitives, one per leaf of the vector IFS, with "
                  "per-instance colour"),
    ('TERRAIN', "Add a fractal terrain mesh with the fractal palette as its material"),
    ('PALETTE', "Make a fractal palette texture (an image datablock)"),
    ('MESH', "Add the iso-surface of the system's volume as a mesh object"),
)

classes = tuple(_generate_operator(kind, text) for kind, text in GENERATE_KINDS) + (IFSFORGE_OT_regenerate,)
