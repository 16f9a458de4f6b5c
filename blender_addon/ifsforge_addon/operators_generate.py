"""Generate and Regenerate. Invoked from the UI they run modally: the work runs on a thread,
the window manager shows its progress and Esc cancels; called from a script (execute) they
run in place. Either way the result is one undo step, and errors become reports."""
import json
import traceback

import bpy
from bpy.props import BoolProperty, PointerProperty, StringProperty

import ifsforge

from . import (generate_image, generate_instances, generate_mesh, generate_palette,  # noqa: F401  (they register)
               generate_terrain, generate_volume)
from . import codec, generators, presets, state
from .jobs import Job
from .properties import IFSFORGE_PG_settings, restore, snapshot, snapshot_settings, snapshot_system, system_values


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
    """What one run makes: from which values (a properties.snapshot: the system and the
    settings), into which datablock (by name, resolved again when the work is done, since the UI
    keeps running meanwhile)."""

    def __init__(self, context, generator, owner, values, new):
        self.generator = generator
        self.values = values
        self.new = new
        base = f"{values['record']['name'] or 'IFS'} {generator.label.lower()}"
        self.name = generators.unique_name(generator, base) if new else owner.name
        settings = generator.resolve(dict(values["settings"]))
        # A generator that reads no system (a palette, random heights) neither needs nor
        # depends on one: an empty design does not stop it, and editing the design does not
        # rename its file.
        system = state.system_of_values(values) if generator.uses_system(settings) else None
        shaped = values if system is not None else generators.without_system(values)
        path = generators.output_path(context, generator, self.name, shaped | {"settings": settings})
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
        owner.ifsforge.origin = self.job.result.get("origin", (0.0, 0.0, 0.0))
        owner.ifsforge.built_from = generators.digest(self.values)
        return owner


def own_data(owner):
    """A duplicate (Shift+D of a volume, Alt+D of anything) shares its datablock with the
    original: regenerating it first gives it a copy of its own, so the original is untouched."""
    data = getattr(owner, "data", None)
    if data is not None and data.users > 1:
        owner.data = data.copy()


class JobOperator:
    """Mixin: subclasses define plan(context) -> Plan, and may define placed(context, owner)
    (what the new datablock gets besides: an image's empty in the viewport)."""
    bl_options = {'REGISTER', 'UNDO'}
    _plan = None
    _timer = None

    def placed(self, context, owner):
        pass

    def done(self, context):
        owner = self._plan.finish(context)
        self.placed(context, owner)
        self.report({'INFO'}, f"{owner.name}: {owner.ifsforge.summary}")
        return {'FINISHED'}

    def execute(self, context):
        try:
            self._plan = self.plan(context)
            self._plan.job.run()
            return self.done(context)
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}

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
            return self.done(context)
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}


def default_system(generator, settings):
    """The system values (properties.SYSTEM_KEYS of a snapshot) of the generator's own sample,
    what a fresh scene's empty design generates from; its view goes into `settings`."""
    system = ifsforge.load(str(presets.sample("systems", generator.default_sample)))
    view = system.render_defaults.get("view")
    if view:
        settings.view = view
    return system_values(codec.system_record(system))


def _generate_operator(kind, description):
    """An IFSFORGE_OT_generate_<kind> class: a new datablock at the 3D cursor from the edited
    system, from the sample `sample`, or, when the design is empty (a fresh scene), from the
    generator's own sample. The operator keeps the system (ifsforge values as JSON) and the
    settings it made the datablock from: F9 "Adjust Last Operation" re-runs it with changed
    values, and an operator preset (shipped, or saved by the user with F9's "+") holds every value
    and makes the same datablock again in any scene."""

    def plan(self, context):
        generator = generators.get(kind)
        reason = generator.missing()
        if reason:
            raise ifsforge.Error(reason)
        owner, system_pg, settings_pg = state.target(context)
        if self.sample:  # into the scene's design (never over a selected object's stored system)
            from .operators_design import load_into  # (operators_design imports this module)
            design = context.scene.ifsforge
            system_pg, settings_pg = design.system, design.settings
            load_into(context, self, system_pg, ifsforge.load(str(presets.sample("systems", self.sample))),
                      settings_pg)
            self.system = json.dumps(snapshot_system(system_pg))
        if not self.adjusted:  # first run: start from the edited system and settings
            restore({"settings": snapshot_settings(settings_pg)}, None, self.settings)
            if not self.sample:
                if state.empty(system_pg) and generator.uses_system(snapshot_settings(self.settings)):
                    values = default_system(generator, self.settings)
                else:
                    values = snapshot_system(system_pg)
                self.system = json.dumps(values)
            self.adjusted = True
        values = json.loads(self.system) if self.system else snapshot_system(system_pg)
        return Plan(context, generator, owner, values | {"settings": snapshot_settings(self.settings)}, new=True)

    def placed(self, context, owner):
        if self.in_viewport and isinstance(owner, bpy.types.Image):
            generators.image_empty(context, owner)

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
        system = None
        if self.system:
            values = json.loads(self.system)
            layout.label(text=f"System: {values['record']['name']}", icon='OUTLINER_OB_POINTCLOUD')
            system = state.analyse_values(values).system
        generators.get(kind).draw(layout, self.settings, system)

    name = kind.lower()
    return type(f"IFSFORGE_OT_generate_{name}", (JobOperator, bpy.types.Operator), {
        "bl_idname": f"ifsforge.generate_{name}", "bl_label": f"Generate {generators.get(kind).label}",
        "bl_description": description, "bl_options": {'REGISTER', 'UNDO', 'PRESET'},
        "plan": plan, "placed": placed, "poll": poll, "draw": draw,
        "__annotations__": {
            # Saved in presets (neither hidden nor SKIP_SAVE), and ignored on a first run
            # (adjusted is False), which takes the edited values instead of the last run's.
            "settings": PointerProperty(type=IFSFORGE_PG_settings),
            "system": StringProperty(name="System", description="The system generated from (ifsforge values, JSON)"),
            "sample": StringProperty(name="Sample", options={'SKIP_SAVE'},
                                     description="A sample system file to generate from (empty: the edited system)"),
            "in_viewport": BoolProperty(
                name="Show in viewport", options={'SKIP_SAVE'},
                description="An image: also add an image empty showing it at the 3D cursor"),
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
        return Plan(context, generator, owner, snapshot(owner.ifsforge.system, owner.ifsforge.settings), new=False)


def regenerate_now(context, owner, source=None):
    """Synchronous regeneration (frame changes, renders, missing files), from the owner's stored
    values or from `source` (its evaluated copy's ifsforge group). Returns an error message or ''."""
    source = source or owner.ifsforge
    try:
        plan = Plan(context, generators.get(owner.ifsforge.kind), owner, snapshot(source.system, source.settings),
                    new=False)
        plan.job.run()
        plan.finish(context)
    except Exception as error:
        return f"{owner.name}: {error}"
    return ""


GENERATE_KINDS = (
    ('IMAGE', "Render the system to a PNG (any chapter-5 algorithm) and load it as an image"),
    ('VOLUME', "Write an OpenVDB volume (density and color grids) and add a Volume object with a "
               "Principled Volume material"),
    ('INSTANCES', "Add a collection of instanced CSG primitives, one per leaf of the vector IFS, with "
                  "per-instance color"),
    ('TERRAIN', "Add a fractal terrain mesh with the fractal palette as its material"),
    ('PALETTE', "Make a fractal palette texture (an image datablock)"),
    ('MESH', "Add the iso-surface of the system's volume as a mesh object"),
)

classes = tuple(_generate_operator(kind, text) for kind, text in GENERATE_KINDS) + (IFSFORGE_OT_regenerate,)
