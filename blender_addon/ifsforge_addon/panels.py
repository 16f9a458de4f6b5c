"""The "IFS" tab of the 3D viewport's sidebar, and a panel for generated images in the image
editor. Panels only draw: the numbers they show come from state.analyse (the core)."""
import bpy
from bpy.types import Menu, Panel, UIList

import ifsforge

from . import files, generators, preview, state
from .properties import COMMON_LAYOUTS, MAX_EXTRA

AXES = "xyz"


class IFSFORGE_UL_maps(UIList):
    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index):
        analysis = state.analyse(data)
        row = layout.row(align=True)
        swatch = row.row()
        swatch.ui_units_x = 1.2
        swatch.prop(item, "color", text="")
        split = row.split(factor=0.45)
        split.prop(item, "name", text="", emboss=False)
        if index < len(analysis.factors):
            s = analysis.factors[index]
            label = split.row()
            label.alert = s >= 1.0
            label.label(text=f"{s:.2f} | {analysis.probabilities[index]:.2f}")


class IFSFORGE_UL_library(UIList):
    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index):
        layout.prop(item, "name", text="", emboss=False, icon='FILE_3D')


class IFSFORGE_MT_layouts(Menu):
    bl_label = "Layouts"

    def draw(self, context):
        for text in COMMON_LAYOUTS:
            op = self.layout.operator("wm.context_set_string", text=text)
            op.data_path = _layout_path(context)
            op.value = text


def _layout_path(context):
    owner, pg, _ = state.target(context)
    prefix = "scene" if isinstance(owner, bpy.types.Scene) else "active_object"
    return f"{prefix}.{pg.path_from_id('layout')}"


class SidebarPanel:
    bl_space_type = 'VIEW_3D'
    bl_region_type = 'UI'
    bl_category = "IFS"


def draw_analysis(layout, analysis, pg):
    box = layout.box()
    if analysis.error:
        col = box.column()
        col.alert = True
        for k, line in enumerate(_wrap(analysis.error, 48)):
            col.label(text=line, icon='ERROR' if k == 0 else 'BLANK1')
        return
    system = analysis.system
    box.label(text=analysis.classification.capitalize(), icon='CHECKMARK')
    box.label(text=f"max s = {max(analysis.factors):.4f} (Eq. 10)")
    if analysis.classification != "hyperbolic":
        box.label(text=f"Σ p log s = {system.average_log_contraction():.4f} (Eq. 14)")
    if pg.morph.enabled:
        box.label(text=f"{len(system)} maps, morph t = {pg.morph.factor:.3f}")


def _wrap(text, width):
    words, lines, line = text.split(), [], ""
    for word in words:
        if line and len(line) + len(word) + 1 > width:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    return lines + [line] if line else lines or [""]


class IFSFORGE_PT_design(SidebarPanel, Panel):
    bl_label = "IFS"

    def draw(self, context):
        layout = self.layout
        owner, pg, _ = state.target(context)
        if isinstance(owner, bpy.types.Object):
            layout.label(text=f"Editing {owner.name} ({owner.ifsforge.kind.lower()})", icon='OBJECT_DATA')
        else:
            layout.label(text="Editing the scene's design", icon='SCENE_DATA')
        row = layout.row(align=True)
        row.operator("ifsforge.load_preset", text="Preset", icon='PRESET')
        row.operator("ifsforge.import_system", text="Import", icon='IMPORT')
        row.operator("ifsforge.new_system", text="New", icon='FILE_NEW').layout = pg.layout if pg.layout else "xy"
        layout.prop(pg, "name")
        row = layout.row(align=True)
        row.prop(pg, "layout")
        row.menu("IFSFORGE_MT_layouts", text="", icon='DOWNARROW_HLT')
        layout.prop(pg, "probabilities")
        if state.empty(pg):  # a fresh scene: say what Generate does rather than what is missing
            box = layout.box()
            box.label(text="No system yet: each generator starts", icon='INFO')
            box.label(text="from its own sample (Preset to pick one)", icon='BLANK1')
            return
        analysis = state.analyse(pg)
        draw_analysis(layout, analysis, pg)
        if pg.morph.enabled:
            layout.label(text=f"Morph {pg.morph.source_name} to {pg.morph.target_name}", icon='SHAPEKEY_DATA')
            layout.prop(pg.morph, "factor")
            return
        row = layout.row()
        row.template_list("IFSFORGE_UL_maps", "", pg, "maps", pg, "active_map", rows=4)
        col = row.column(align=True)
        col.operator("ifsforge.map_add", text="", icon='ADD')
        col.operator("ifsforge.map_remove", text="", icon='REMOVE')
        col.operator("ifsforge.map_duplicate", text="", icon='DUPLICATE')
        col.separator()
        col.operator("ifsforge.map_move", text="", icon='TRIA_UP').direction = 'UP'
        col.operator("ifsforge.map_move", text="", icon='TRIA_DOWN').direction = 'DOWN'


class IFSFORGE_PT_map(SidebarPanel, Panel):
    bl_label = "Map"
    bl_parent_id = "IFSFORGE_PT_design"

    @classmethod
    def poll(cls, context):
        return active_map(context) is not None

    def draw(self, context):
        layout = self.layout
        pg, m, channel_layout = active_map(context)
        s = channel_layout.spatial_dims
        layout.use_property_split = True
        col = layout.column(align=True)
        _vector(col, m, "translation", s, "Translation")
        col = layout.column(align=True)
        if s == 2:  # Eq. 5: the angles of the two axes (equal: a rotation)
            col.prop(m, "rotation", index=0, text="Angle X")
            col.prop(m, "rotation", index=1, text="Y")
        else:
            _vector(col, m, "rotation", 3, "Rotation")
        col = layout.column(align=True)
        _vector(col, m, "scale", s, "Scale")
        col = layout.column(align=True)
        if s == 2:
            col.prop(m, "shear", index=0, text="Shear")
        else:
            for k, label in enumerate(("Shear XY", "XZ", "YZ")):
                col.prop(m, "shear", index=k, text=label)
        row = layout.row(align=True, heading="Reflect")
        for k in range(s):
            row.prop(m, "reflect", index=k, text=AXES[k].upper(), toggle=True)
        sub = layout.row()
        sub.enabled = pg.probabilities == 'explicit'
        sub.prop(m, "probability")


def active_map(context):
    """(system, map, ChannelLayout) of the panel's active map, or None."""
    pg = state.target(context)[1]
    if pg.morph.enabled or not 0 <= pg.active_map < len(pg.maps):
        return None
    try:
        return pg, pg.maps[pg.active_map], ifsforge.ChannelLayout(pg.layout)
    except ifsforge.InputError:
        return None


class IFSFORGE_PT_channels(SidebarPanel, Panel):
    """The extra channels of the active map: one row of the matrix each (Eq. 97-107)."""
    bl_label = "Channels"
    bl_parent_id = "IFSFORGE_PT_map"

    @classmethod
    def poll(cls, context):
        found = active_map(context)
        return found is not None and found[2].dim > found[2].spatial_dims

    def draw(self, context):
        pg, m, channel_layout = active_map(context)
        names, s = channel_layout.names, channel_layout.spatial_dims
        layout = self.layout
        layout.use_property_split = True
        for k, row in enumerate(m.channels):
            col = layout.column(align=True)
            for j, name in enumerate(names):
                col.prop(row, "coefficients", index=j, text=f"{names[s + k]}' · {name}" if j == 0 else f"· {name}")
            col.prop(row, "offset", text="+")


class IFSFORGE_PT_feedback(SidebarPanel, Panel):
    """How the extra channels enter the position (zero for most systems)."""
    bl_label = "Channels into Position"
    bl_parent_id = "IFSFORGE_PT_map"
    bl_options = {'DEFAULT_CLOSED'}

    @classmethod
    def poll(cls, context):
        return IFSFORGE_PT_channels.poll(context)

    def draw(self, context):
        pg, m, channel_layout = active_map(context)
        names, s = channel_layout.names, channel_layout.spatial_dims
        layout = self.layout
        layout.use_property_split = True
        for r in range(s):
            col = layout.column(align=True)
            for j in range(channel_layout.dim - s):
                col.prop(m, "coupling", index=r * MAX_EXTRA + j,
                         text=f"{AXES[r]}' · {names[s + j]}" if j == 0 else f"· {names[s + j]}")


def _vector(col, m, prop, count, label):
    for k in range(count):
        col.prop(m, prop, index=k, text=f"{label} {AXES[k].upper()}" if k == 0 else AXES[k].upper())


class IFSFORGE_PT_preview(SidebarPanel, Panel):
    bl_label = "Preview"
    bl_parent_id = "IFSFORGE_PT_design"

    def draw_header(self, context):
        self.layout.prop(context.scene.ifsforge.preview, "show", text="")

    def draw(self, context):
        layout = self.layout
        settings = context.scene.ifsforge.preview
        layout.active = settings.show
        layout.prop(settings, "count")
        layout.prop(settings, "coloring")
        row = layout.row(align=True)
        row.prop(settings, "point_size")
        row.prop(settings, "show_frames", text="", icon='MOD_WIREFRAME')
        row.prop(settings, "highlight_active", text="", icon='RESTRICT_SELECT_OFF')
        if preview.current.error:
            layout.label(text=preview.current.error[:60], icon='ERROR')
        elif preview.current.cloud is not None:
            layout.label(text=f"{preview.current.cloud.count:,} points in {1e3 * preview.current.seconds:.1f} ms")


class IFSFORGE_PT_collage(SidebarPanel, Panel):
    """A target picture behind the 2D design and the collage distance to it (Eq. 41-42)."""
    bl_label = "Target and Collage"
    bl_parent_id = "IFSFORGE_PT_design"
    bl_options = {'DEFAULT_CLOSED'}

    def draw_header(self, context):
        self.layout.prop(context.scene.ifsforge.collage, "show", text="")

    def draw(self, context):
        layout = self.layout
        settings = context.scene.ifsforge.collage
        layout.template_ID(settings, "image", open="image.open")
        layout.prop(settings, "filepath")
        layout.prop(settings, "window")
        row = layout.row(align=True)
        row.prop(settings, "threshold")
        row.prop(settings, "raster")
        if settings.image is None:
            layout.label(text="Choose a target picture", icon='INFO')
        elif settings.error:
            layout.label(text=settings.error[:60], icon='ERROR')
        elif settings.distance_pixels >= 0:
            layout.label(text=f"Collage distance {settings.distance_pixels:.2f} px = {settings.distance:.4g}",
                         icon='MOD_MASK')
            bound = f"{settings.bound:.4g}" if settings.bound >= 0 else "unbounded (a map does not contract)"
            layout.label(text=f"Attractor within {bound} ({1e3 * settings.seconds:.1f} ms)")


class IFSFORGE_PT_library(SidebarPanel, Panel):
    bl_label = "Library and Morph"
    bl_parent_id = "IFSFORGE_PT_design"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        data = context.scene.ifsforge
        pg = state.target(context)[1]
        row = layout.row()
        row.template_list("IFSFORGE_UL_library", "", data, "library", data, "library_index", rows=3)
        col = row.column(align=True)
        col.operator("ifsforge.library_save", text="", icon='ADD')
        col.operator("ifsforge.library_remove", text="", icon='REMOVE')
        col.operator("ifsforge.library_load", text="", icon='FILE_REFRESH')
        layout.prop_search(data, "morph_source", data, "library")
        layout.prop_search(data, "morph_target", data, "library")
        row = layout.row(align=True)
        row.operator("ifsforge.morph_set", icon='SHAPEKEY_DATA')
        row.operator("ifsforge.morph_apply")
        row = layout.row(align=True)
        row.prop(pg.morph, "enabled", text="Morph", toggle=True)
        row.prop(pg.morph, "factor")


class IFSFORGE_PT_generate(SidebarPanel, Panel):
    bl_label = "Generate"
    bl_parent_id = "IFSFORGE_PT_design"

    def draw(self, context):
        layout = self.layout
        owner, pg, settings = state.target(context)
        layout.use_property_split = True
        layout.prop(settings, "seed")
        layout.prop(context.scene.ifsforge, "cache_folder")
        if files.missing():
            layout.operator("ifsforge.regenerate_missing", icon='ERROR')
        if state.generated(owner):
            box = layout.box()
            box.label(text=owner.ifsforge.summary, icon='INFO')
            row = box.row()
            row.operator("ifsforge.regenerate", icon='FILE_REFRESH')
            row.prop(owner.ifsforge, "regenerate_on_frame", text="Every frame")
            row = box.row()
            row.operator("ifsforge.bake_animation", icon='RENDER_ANIMATION')
            if owner.ifsforge.baked:
                row.operator("ifsforge.free_bake", icon='TRASH')
            box.operator("ifsforge.copy_to_design", icon='COPYDOWN')


GENERATE_KINDS = (('IMAGE', "Image", 'IMAGE_DATA'), ('VOLUME', "Volume", 'VOLUME_DATA'),
                  ('INSTANCES', "Instances", 'MOD_PARTICLE_INSTANCE'), ('TERRAIN', "Terrain", 'RNDCURVE'),
                  ('PALETTE', "Palette", 'COLOR'), ('MESH', "Iso-surface", 'MESH_DATA'))


def _generator_panel(kind, label, icon):
    """A sub-panel of Generate: the generator's settings and its button, or why it is missing."""

    def draw(self, context):
        layout = self.layout
        if not generators.registered(kind):
            layout.label(text="not available in this version", icon='ERROR')
            return
        generator = generators.get(kind)
        reason = generator.missing()
        if reason:
            layout.label(text=reason, icon='ERROR')
            return
        owner, pg, settings = state.target(context)
        layout.use_property_split = True
        generator.draw(layout, settings, state.analyse(pg).system)
        layout.operator(f"ifsforge.generate_{kind.lower()}", text=f"Generate {label}", icon=icon)

    return type(f"IFSFORGE_PT_generate_{kind.lower()}", (SidebarPanel, Panel), {
        "bl_label": label, "bl_parent_id": "IFSFORGE_PT_generate", "bl_options": {'DEFAULT_CLOSED'}, "draw": draw})


GENERATOR_PANELS = tuple(_generator_panel(*entry) for entry in GENERATE_KINDS)


class IFSFORGE_PT_export(SidebarPanel, Panel):
    bl_label = "Export"
    bl_parent_id = "IFSFORGE_PT_design"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        row = self.layout.row(align=True)
        row.operator("ifsforge.export_json", text="JSON", icon='EXPORT')
        row.operator("ifsforge.export_povray", text="POV-Ray", icon='EXPORT')


class IFSFORGE_PT_image(Panel):
    bl_space_type = 'IMAGE_EDITOR'
    bl_region_type = 'UI'
    bl_category = "IFS"
    bl_label = "IFS"

    @classmethod
    def poll(cls, context):
        return state.generated(getattr(context.space_data, "image", None))

    def draw(self, context):
        layout = self.layout
        image = context.space_data.image
        data = image.ifsforge
        layout.label(text=data.summary, icon='INFO')
        layout.use_property_split = True
        generators.get(data.kind).draw(layout, data.settings, state.analyse(data.system).system)
        layout.prop(data.settings, "seed")
        draw_analysis(layout, state.analyse(data.system), data.system)
        row = layout.row()
        row.operator("ifsforge.regenerate", icon='FILE_REFRESH').image = image.name
        row.operator("ifsforge.copy_to_design", icon='COPYDOWN').image = image.name


classes = (IFSFORGE_UL_maps, IFSFORGE_UL_library, IFSFORGE_MT_layouts, IFSFORGE_PT_design, IFSFORGE_PT_map,
           IFSFORGE_PT_channels, IFSFORGE_PT_feedback,
           IFSFORGE_PT_preview, IFSFORGE_PT_collage, IFSFORGE_PT_library, IFSFORGE_PT_generate, *GENERATOR_PANELS, IFSFORGE_PT_export,
           IFSFORGE_PT_image)
