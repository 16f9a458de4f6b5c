"""Editing the system: presets, import and export, the map list, the library of saved systems
and the morph between two of them. Every operator edits the system the panel shows
(state.target): the scene's design, or the active generated object's stored system."""
import json

import bpy
from bpy.props import EnumProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper
from mathutils import Vector

import ifsforge

from . import codec, generators, presets, preview, state
from .operators_generate import report_error
from .properties import read_record, restore, snapshot, write_map, write_record


def presets_folder():
    return presets.folder("systems")


_preset_items = []


def preset_items(self=None, context=None):
    """Every .json system and every entry of every .ifs file of the presets folder (the list is
    kept: Blender needs enum item strings to outlive the call)."""
    if not _preset_items:
        folder = presets_folder()
        for path in sorted(folder.glob("*.json")) if folder else ():
            name = json.loads(path.read_text()).get("name", path.stem)
            _preset_items.append((path.name, name, str(path)))
        for path in sorted(folder.glob("*.ifs")) if folder else ():
            for entry in ifsforge.read_fractint(str(path)):
                _preset_items.append((f"{path.name}:{entry.name}", f"{entry.name} ({path.name})", str(path)))
        if not _preset_items:
            _preset_items.append(('NONE', "No presets found", ""))
    return _preset_items


def load_into(context, operator, pg, system, settings=None):
    """Puts an ifsforge.Ifs into a system PropertyGroup (and its view into `settings`, by default
    the edited ones); warns about what the map list cannot hold."""
    left_out = codec.extensions(ifsforge.to_json(system))
    pg.morph.enabled = False
    write_record(pg, codec.system_record(system))
    pg.active_map = 0
    view = system.render_defaults.get("view")
    if view:
        (settings or state.target(context)[2]).view = view
    if left_out:
        operator.report({'WARNING'}, f"'{system.name}': {', '.join(left_out)} left out (the map list edits "
                                     "ordinary systems)")


def save_to_library(scene, system):
    """Adds (or replaces, by name) a system in the scene's library."""
    library = scene.ifsforge.library
    item = library.get(system.name) or library.add()
    item.name = system.name
    item.json = ifsforge.to_json(system)
    scene.ifsforge.library_index = list(library).index(item)
    return item


class DesignOperator:
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        try:
            self.edit(context, *state.target(context))
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        return {'FINISHED'}


class IFSFORGE_OT_load_preset(DesignOperator, bpy.types.Operator):
    """Load a system from the sample library"""
    bl_idname = "ifsforge.load_preset"
    bl_label = "Load Preset"
    bl_property = "preset"
    preset: EnumProperty(name="Preset", items=preset_items)

    def invoke(self, context, event):
        context.window_manager.invoke_search_popup(self)
        return {'RUNNING_MODAL'}

    def edit(self, context, owner, pg, settings):
        if self.preset == 'NONE':
            raise ifsforge.FileError("no presets folder: run blender_addon/install.sh")
        load_into(context, self, pg, ifsforge.load(str(presets_folder() / self.preset)))


class IFSFORGE_OT_import(DesignOperator, bpy.types.Operator, ImportHelper):
    """Import a system from ifsforge JSON or a Fractint .ifs file (every entry goes into the library)"""
    bl_idname = "ifsforge.import_system"
    bl_label = "Import IFS"
    filter_glob: StringProperty(default="*.json;*.ifs", options={'HIDDEN'})
    entry: StringProperty(name="Entry", description="Fractint entry to edit (empty: the first)")

    def edit(self, context, owner, pg, settings):
        systems = codec.load_entries(self.filepath)
        chosen = systems[0]
        if self.entry:
            matches = [s for s in systems if s.name == self.entry]
            if not matches:
                raise ifsforge.InputError(f"'{self.filepath}' has no entry '{self.entry}' (it has: "
                                          f"{', '.join(s.name for s in systems)})")
            chosen = matches[0]
        for system in systems:
            save_to_library(context.scene, system)
        load_into(context, self, pg, chosen)


class IFSFORGE_OT_export_json(bpy.types.Operator, ExportHelper):
    """Write the system as ifsforge/1 JSON"""
    bl_idname = "ifsforge.export_json"
    bl_label = "Export IFS JSON"
    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def invoke(self, context, event):
        self.filepath = (state.target(context)[1].name or "system") + ".json"
        return ExportHelper.invoke(self, context, event)

    def execute(self, context):
        try:
            ifsforge.write_json(self.filepath, state.system_of(state.target(context)[1]))
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        self.report({'INFO'}, f"wrote {self.filepath}")
        return {'FINISHED'}


class IFSFORGE_OT_new_system(DesignOperator, bpy.types.Operator):
    """Start a new system of three half-size maps in the chosen layout"""
    bl_idname = "ifsforge.new_system"
    bl_label = "New System"
    layout: StringProperty(name="Layout", default="xy")

    def edit(self, context, owner, pg, settings):
        ifsforge.ChannelLayout(self.layout)  # validates
        maps = [codec.default_map(i, 3, self.layout) for i in range(3)]
        pg.morph.enabled = False
        write_record(pg, {"name": "untitled", "description": "", "layout": self.layout,
                          "probabilities": "jacobian", "maps": maps})


class IFSFORGE_OT_map_add(DesignOperator, bpy.types.Operator):
    """Add a map (a half-size copy)"""
    bl_idname = "ifsforge.map_add"
    bl_label = "Add Map"

    def edit(self, context, owner, pg, settings):
        ifsforge.ChannelLayout(pg.layout)
        index = len(pg.maps)
        write_map(pg.maps.add(), codec.default_map(index, index + 1, pg.layout), f"Map {index + 1}")
        pg.active_map = index


class IFSFORGE_OT_map_remove(DesignOperator, bpy.types.Operator):
    """Remove the active map"""
    bl_idname = "ifsforge.map_remove"
    bl_label = "Remove Map"

    @classmethod
    def poll(cls, context):
        return len(state.target(context)[1].maps) > 1

    def edit(self, context, owner, pg, settings):
        pg.maps.remove(pg.active_map)
        pg.active_map = max(0, min(pg.active_map, len(pg.maps) - 1))


class IFSFORGE_OT_map_duplicate(DesignOperator, bpy.types.Operator):
    """Duplicate the active map (the copy comes right after it)"""
    bl_idname = "ifsforge.map_duplicate"
    bl_label = "Duplicate Map"

    @classmethod
    def poll(cls, context):
        return len(state.target(context)[1].maps) > 0

    def edit(self, context, owner, pg, settings):
        source = read_record(pg)["maps"][pg.active_map]
        item = pg.maps.add()
        write_map(item, source, pg.maps[pg.active_map].name + " copy")
        pg.maps.move(len(pg.maps) - 1, pg.active_map + 1)
        pg.active_map += 1


class IFSFORGE_OT_map_move(DesignOperator, bpy.types.Operator):
    """Move the active map up or down the list"""
    bl_idname = "ifsforge.map_move"
    bl_label = "Move Map"
    direction: EnumProperty(items=(('UP', "Up", ""), ('DOWN', "Down", "")))

    def edit(self, context, owner, pg, settings):
        to = pg.active_map + (-1 if self.direction == 'UP' else 1)
        if 0 <= to < len(pg.maps):
            pg.maps.move(pg.active_map, to)
            pg.active_map = to


class IFSFORGE_OT_library_save(DesignOperator, bpy.types.Operator):
    """Save the edited system in the scene's library (for morphing and recall)"""
    bl_idname = "ifsforge.library_save"
    bl_label = "Save to Library"

    def edit(self, context, owner, pg, settings):
        save_to_library(context.scene, state.system_of(pg))


class IFSFORGE_OT_library_load(DesignOperator, bpy.types.Operator):
    """Edit the selected saved system"""
    bl_idname = "ifsforge.library_load"
    bl_label = "Load from Library"

    @classmethod
    def poll(cls, context):
        data = context.scene.ifsforge
        return 0 <= data.library_index < len(data.library)

    def edit(self, context, owner, pg, settings):
        item = context.scene.ifsforge.library[context.scene.ifsforge.library_index]
        load_into(context, self, pg, ifsforge.parse_json(item.json, item.name))


class IFSFORGE_OT_library_remove(DesignOperator, bpy.types.Operator):
    """Remove the selected saved system"""
    bl_idname = "ifsforge.library_remove"
    bl_label = "Remove from Library"

    @classmethod
    def poll(cls, context):
        data = context.scene.ifsforge
        return 0 <= data.library_index < len(data.library)

    def edit(self, context, owner, pg, settings):
        data = context.scene.ifsforge
        data.library.remove(data.library_index)
        data.library_index = max(0, data.library_index - 1)


class IFSFORGE_OT_morph_set(DesignOperator, bpy.types.Operator):
    """Morph between the two chosen saved systems (keyframe the factor to animate)"""
    bl_idname = "ifsforge.morph_set"
    bl_label = "Set Morph"

    def edit(self, context, owner, pg, settings):
        data = context.scene.ifsforge
        ends = []
        for name in (data.morph_source, data.morph_target):
            item = data.library.get(name)
            if item is None:
                raise ifsforge.InputError(f"choose two saved systems to morph between ('{name}' is not in the library)")
            ends.append(item)
        start = ifsforge.parse_json(ends[0].json, ends[0].name)
        end = ifsforge.parse_json(ends[1].json, ends[1].name)
        ifsforge.morph(start, end, 0.5)  # refuses different layouts before anything changes
        morph = pg.morph
        morph.source, morph.target = ends[0].json, ends[1].json
        morph.source_name, morph.target_name = ends[0].name, ends[1].name
        morph.enabled = True


class IFSFORGE_OT_morph_apply(DesignOperator, bpy.types.Operator):
    """Replace the map list by the morphed system at the current factor"""
    bl_idname = "ifsforge.morph_apply"
    bl_label = "Apply Morph"

    @classmethod
    def poll(cls, context):
        return state.target(context)[1].morph.enabled

    def edit(self, context, owner, pg, settings):
        system = state.system_of(pg)
        pg.morph.enabled = False
        write_record(pg, codec.system_record(system))


class IFSFORGE_OT_copy_to_design(DesignOperator, bpy.types.Operator):
    """Copy the system stored on a generated datablock into the scene's design"""
    bl_idname = "ifsforge.copy_to_design"
    bl_label = "Copy to Design"
    image: StringProperty(name="Image", description="A generated image (empty: the active object)")

    def execute(self, context):
        owner = bpy.data.images.get(self.image) if self.image else context.active_object
        if not state.generated(owner):
            self.report({'ERROR'}, "nothing to copy: no generated datablock")
            return {'CANCELLED'}
        design = context.scene.ifsforge
        restore(snapshot(owner.ifsforge.system, owner.ifsforge.settings), design.system, design.settings)
        return {'FINISHED'}


class IFSFORGE_OT_view_preview(bpy.types.Operator):
    """Frame the previewed attractor in the viewport"""
    bl_idname = "ifsforge.view_preview"
    bl_label = "View Preview"

    @classmethod
    def poll(cls, context):
        return context.area is not None and context.area.type == 'VIEW_3D'

    def execute(self, context):
        cloud = preview.current.update(context)
        if cloud is None:
            self.report({'ERROR'}, preview.current.error or "nothing to preview")
            return {'CANCELLED'}
        owner, pg, _ = state.target(context)
        spatial = state.analyse(pg).system.spatial_dims
        lo, hi = (Vector(list(b[:spatial]) + [0.0] * (3 - spatial)) for b in cloud.bounds)
        in_system_space = isinstance(owner, bpy.types.Object) and owner.ifsforge.kind in preview.SYSTEM_SPACE
        matrix = generators.system_matrix(owner) if in_system_space else None
        centre = (lo + hi) / 2
        view = context.space_data.region_3d
        view.view_location = matrix @ centre if matrix is not None else centre
        view.view_distance = 1.2 * max((hi - lo).length, 1e-3)
        return {'FINISHED'}


classes = (IFSFORGE_OT_load_preset, IFSFORGE_OT_view_preview, IFSFORGE_OT_import, IFSFORGE_OT_export_json,
           IFSFORGE_OT_new_system,
           IFSFORGE_OT_map_add, IFSFORGE_OT_map_remove, IFSFORGE_OT_map_duplicate, IFSFORGE_OT_map_move,
           IFSFORGE_OT_library_save, IFSFORGE_OT_library_load, IFSFORGE_OT_library_remove,
           IFSFORGE_OT_morph_set, IFSFORGE_OT_morph_apply, IFSFORGE_OT_copy_to_design)
