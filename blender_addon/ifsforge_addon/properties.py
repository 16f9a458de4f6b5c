"""The add-on's data: the system being designed (on the scene) and the system and settings
each generated datablock keeps (on the object or image), so Regenerate can rebuild it and
the values are saved with the .blend and can be keyframed."""
import bpy
import numpy as np
from bpy.props import (BoolProperty, BoolVectorProperty, CollectionProperty, EnumProperty, FloatProperty,
                       FloatVectorProperty, IntProperty, PointerProperty, StringProperty)
from bpy.types import PropertyGroup

import ifsforge
from ifsforge import media

from . import codec

TERRAIN = ifsforge.terrain_defaults  # the core's, as the command line's: one recipe, one terrain

MAX_DIM = 8          # kMaxDim of the core
MAX_EXTRA = 6        # channels beyond the 2 or 3 spatial ones
# The core's settings structs: each default is written once, in C++.
RENDER, TONE, DRAW = ifsforge.RenderOptions(), ifsforge.ToneOptions(), ifsforge.DrawOptions()
VOLUME, ISO, INSTANCE = ifsforge.VolumeOptions(), ifsforge.IsoSurfaceOptions(), ifsforge.InstanceOptions()
PREVIEW = ifsforge.PreviewOptions()
COMMON_LAYOUTS = ("xy", "xyz", "xy+gray", "xy+rgb", "xy+hsi", "xy+rgba", "xyz+gray", "xyz+rgb", "xyz+hsi",
                  "xyz+rgba", "xyz+k", "xyz+rgb+k")


def tag_redraw(context=None):
    """Viewports redraw; their draw handler notices the change and rebuilds the preview."""
    wm = bpy.context.window_manager if context is None else context.window_manager
    if wm is None:
        return
    for window in wm.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


def _changed(self, context):
    from . import collage  # collage imports state, which imports this module
    collage.refresh(context)
    tag_redraw(context)


def _target_file_changed(self, context):
    """A target picture given by path becomes an image datablock (what the viewport draws)."""
    if self.filepath:
        try:
            self.image = bpy.data.images.load(bpy.path.abspath(self.filepath), check_existing=True)
        except RuntimeError as error:
            self.error = str(error)
            return
    _changed(self, context)


def _layout_changed(self, context):
    fit_channels(self)
    tag_redraw(context)


def _piece_color(self):
    # The map's index is the last [k] of its data path ("...maps[3]").
    path = self.path_from_id()
    index = int(path[path.rindex("[") + 1:-1])
    return ifsforge.piece_color(index)


class IFSFORGE_PG_channel_row(PropertyGroup):
    """One extra channel of a map: c' = sum_j coefficients[j] x_j + offset (Eq. 97-107)."""
    coefficients: FloatVectorProperty(name="Coefficients", size=MAX_DIM, precision=4, step=1, update=_changed)
    offset: FloatProperty(name="Offset", precision=4, step=1, update=_changed)


class IFSFORGE_PG_map(PropertyGroup):
    """One affine map in the parameters of Eq. 5 (2D) and its 3D analogue."""
    name: StringProperty(name="Name", default="Map")
    translation: FloatVectorProperty(name="Translation", size=3, precision=4, step=1, update=_changed)
    rotation: FloatVectorProperty(
        name="Rotation", size=3, precision=2, step=100, update=_changed,
        description="Degrees. 2D: the angles of the x and y axes (equal: a rotation; different: a skew). "
                    "3D: about x, y, z")
    scale: FloatVectorProperty(name="Scale", size=3, default=(0.5, 0.5, 0.5), precision=4, step=1, update=_changed)
    shear: FloatVectorProperty(name="Shear", size=3, precision=4, step=1, update=_changed,
                               description="2D: h (first value). 3D: hxy, hxz, hyz")
    reflect: BoolVectorProperty(name="Reflect", size=3, update=_changed)
    probability: FloatProperty(name="Probability", default=1.0, min=0.0, soft_max=1.0, precision=4, step=1,
                               update=_changed, description="Relative weight (normalized over the maps)")
    channels: CollectionProperty(type=IFSFORGE_PG_channel_row)
    coupling: FloatVectorProperty(
        name="Coupling", size=3 * MAX_EXTRA, precision=4, step=1, update=_changed,
        description="How the extra channels feed back into the position (row per spatial axis)")
    color: FloatVectorProperty(name="Piece color", subtype='COLOR', size=4, get=_piece_color,
                               description="The color of this map's piece in the preview")


class IFSFORGE_PG_morph(PropertyGroup):
    """A morph between two saved systems; the factor can be keyframed (continuity theorem)."""
    enabled: BoolProperty(name="Morph", update=_changed,
                          description="Show the system between the two saved systems instead of the map list")
    source: StringProperty(name="From")   # ifsforge/1 JSON
    target: StringProperty(name="To")
    source_name: StringProperty(name="From")
    target_name: StringProperty(name="To")
    factor: FloatProperty(name="Factor", min=0.0, max=1.0, subtype='FACTOR', update=_changed,
                          description="0: the first system, 1: the second")


class IFSFORGE_PG_system(PropertyGroup):
    name: StringProperty(name="Name", default="untitled", update=_changed)
    description: StringProperty(name="Description")
    layout: StringProperty(name="Layout", default="xy", update=_layout_changed,
                           description="Meaning of the dimensions: xy or xyz, then +gray, +rgb, +hsi, +rgba, "
                                       "+alpha, +k (e.g. xyz+rgb)")
    probabilities: EnumProperty(
        name="Probabilities", update=_changed, default='explicit',
        items=(('explicit', "Per map", "Each map's probability"),
               ('jacobian', "Jacobian", "Proportional to |det| of each map (Eq. 46)"),
               ('uniform', "Uniform", "Equal for every map")))
    maps: CollectionProperty(type=IFSFORGE_PG_map)
    # The layout the maps' channel rows were made for: rows are rebuilt when it changes.
    rows_layout: StringProperty(default="xy")
    active_map: IntProperty(name="Active map", update=_changed)
    morph: PointerProperty(type=IFSFORGE_PG_morph)


def _renderer_items():
    return [(name, name, text) for name, text in ifsforge.renderers() if name != "color-stealing"]


RENDERER_ITEMS = _renderer_items()
VOLUME_RENDERER_ITEMS = [(name, name, text) for name, text in getattr(ifsforge, "volume_renderers", list)()] or [
    ("prr", "prr", "not in this ifsforge build")]


class IFSFORGE_PG_settings(PropertyGroup):
    """How a datablock is generated from its system."""
    seed: IntProperty(name="Seed", min=0, default=RENDER.seed)
    # 2D image
    image_size: IntProperty(name="Size", min=16, max=16384, default=RENDER.width, description="Pixels per side")
    image_algorithm: EnumProperty(name="Algorithm", items=RENDERER_ITEMS)
    image_mode: EnumProperty(name="Mode", default=TONE.mode, items=(
        ('auto', "Auto", "Shaded for 3D, color when the layout has color, else density"),
        ('binary', "Binary", "Coverage"), ('density', "Density", "Log density"),
        ('color', "Color", "The color channels"), ('shaded', "Shaded", "Lit z-buffer (3D systems)")))
    view: FloatVectorProperty(name="View", size=2, default=tuple(DRAW.view),
                              description="Yaw and pitch in degrees (3D systems)")
    # Volumes (6.2.3.2, 6.5.3.1) and their iso-surfaces
    volume_resolution: IntProperty(name="Resolution", min=8, max=2048, default=VOLUME.resolution,
                                   description="Voxels along the longest side of the attractor's box")
    volume_algorithm: EnumProperty(name="Algorithm", items=VOLUME_RENDERER_ITEMS, default="prr")
    volume_density: EnumProperty(name="Density", default=VOLUME.density, items=(
        ('binary', "Binary", "1 in every occupied voxel"), ('hits', "Hits", "Points or leaves per voxel"),
        ('measure', "Measure", "The voxel's share of the invariant measure")))
    volume_strength: FloatProperty(
        name="Material density", min=0.0, default=media.DENSITY,
        description="The volume's average density over its box, per world unit: the same look at any "
                    "resolution and density mode (Regenerate applies it to the material)")
    mesh_iso: FloatProperty(name="Iso value", min=0.0, max=1.0, default=ISO.iso,
                            description="Iso-surface of the occupancy (0..1)")
    custom_normals: BoolProperty(
        name="Core normals", default=False,
        description="Store the core's per-vertex normals as custom split normals (terrains, iso-surfaces). Off: "
                    "smooth shading from the faces, much faster to build and to evaluate")
    mesh_adaptivity: FloatProperty(name="Adaptivity", min=0.0, max=1.0, default=ISO.adaptivity,
                                   description="0: every voxel face; higher merges flat regions")
    # CSG instances (vector recursive rendering, 5.8.2)
    instance_depth: IntProperty(name="Depth", min=0, max=24, default=INSTANCE.depth,
                                description="Recursion depth L: N^L instances (0: the largest L with N^L <= 50000)")
    instance_primitives: StringProperty(
        name="Primitives", default=",".join(INSTANCE.primitives),
        description="A primitive, or a comma list the k channel picks from: sphere, box, cone, cylinder, torus, "
                    "circle, square, triangle, line")
    instance_scale: FloatProperty(name="Scale factor", min=0.0, default=INSTANCE.scale_factor, description="sf of Eq. 60")
    instance_color_by: EnumProperty(name="Color", default=INSTANCE.color_source, items=(
        ('auto', "Auto", "The color channels if the layout has them, else the first map of the address"),
        ('channels', "Channels", "The layout's color channels (Eq. 101)"),
        ('first-map', "First map", "The first map of each leaf's address"),
        ('last-map', "Last map", "The last map of each leaf's address"),
        ('constant', "Constant", "One color")))
    # Terrains (6.1.3.4) and fractal palettes (6.1.3.3)
    terrain_source: EnumProperty(name="Heights", default='ATTRACTOR', items=(
        ('ATTRACTOR', "Attractor", "Control heights sampled from the system's density image"),
        ('RANDOM', "Random", "Seeded random control heights"),
        ('RECIPE', "Recipe", "A terrain recipe file (ifsforge-terrain/1)")))
    terrain_recipe: StringProperty(name="Recipe", subtype='FILE_PATH')
    terrain_grid: EnumProperty(name="Grid", default='regular', items=(
        ('regular', "Regular", ""), ('irregular', "Irregular", "Displaced control points"),
        ('circular', "Circular", "Leading circles around a centre")))
    terrain_controls: IntProperty(name="Control points", min=5, max=65, default=TERRAIN["controls"],
                                  description="Control heights along each side (circular: circles and angles)")
    terrain_roughness: FloatVectorProperty(name="Roughness", size=2, min=-0.99, max=0.99,
                                           default=(TERRAIN["roughness"], TERRAIN["roughness"]),
                                           description="|a22| of Eq. 94 along and across the leading vectors")
    terrain_resolution: IntProperty(name="Resolution", min=17, max=4097, default=TERRAIN["samples"],
                                    description="Samples along each side")
    terrain_size: FloatProperty(name="Size", min=0.01, default=ifsforge.TerrainControlsOptions().size_x, subtype='DISTANCE')
    terrain_height: FloatProperty(name="Height", min=0.0, default=1.0, subtype='DISTANCE',
                                  description="From the lowest to the highest point of the terrain")
    palette_recipe: StringProperty(name="Palette", subtype='FILE_PATH',
                                   description="A palette recipe (ifsforge-palette/1); empty: the sample 'earth'")
    palette_entries: IntProperty(name="Entries", min=2, max=65536, default=ifsforge.PaletteRecipe().entries)
    palette_rows: IntProperty(name="Rows", min=1, max=4096, default=16, description="Palette image height")


class IFSFORGE_PG_generated(PropertyGroup):
    """Stored on every object or image the add-on generates."""
    kind: EnumProperty(name="Kind", default='NONE', items=(
        ('NONE', "None", ""), ('IMAGE', "Image", "2D rendering"), ('VOLUME', "Volume", "OpenVDB volume"),
        ('INSTANCES', "Instances", "CSG instances"), ('TERRAIN', "Terrain", "Terrain mesh"),
        ('PALETTE', "Palette", "Fractal palette texture"), ('MESH', "Iso-surface", "Iso-surface mesh")))
    system: PointerProperty(type=IFSFORGE_PG_system)
    settings: PointerProperty(type=IFSFORGE_PG_settings)
    output: StringProperty(name="File", subtype='FILE_PATH', description="The file the generator wrote")
    summary: StringProperty(name="Result")
    regenerate_on_frame: BoolProperty(
        name="Regenerate on frame change", default=True,
        description="On every frame (renders included), rebuild this datablock when a stored value changed "
                    "(keyframes, drivers, NLA, scripts)")
    # generators.digest() of the values the datablock was last built from.
    built_from: StringProperty(options={'HIDDEN'})
    # The system's point at the object's origin (the centre of what was generated): the data is
    # stored relative to it (generators.system_matrix).
    origin: FloatVectorProperty(name="Origin in system", size=3, subtype='XYZ', options={'HIDDEN'})
    baked: BoolProperty(name="Baked", description="Its frames are files Blender reads natively (Bake Animation)")


class IFSFORGE_PG_preview(PropertyGroup):
    show: BoolProperty(name="Preview", default=True, update=_changed, description="Draw the attractor in the viewport")
    count: IntProperty(name="Points", default=PREVIEW.count, min=1000, max=5000000, update=_changed)
    coloring: EnumProperty(name="Color", update=_changed, items=(
        ('auto', "Auto", "The color channels when the layout has them, else the pieces"),
        ('pieces', "Pieces", "Each map's piece w_i(A) in its own color: the collage"),
        ('channels', "Channels", "The layout's color channels")))
    point_size: FloatProperty(name="Point size", default=2.0, min=1.0, max=10.0, update=_changed)
    show_frames: BoolProperty(name="Collage frames", default=True, update=_changed,
                              description="The bounding box and its image under each map")
    highlight_active: BoolProperty(name="Highlight active map", default=True, update=_changed)


class IFSFORGE_PG_collage(PropertyGroup):
    """A target picture for the 2D design and the collage distance to it (Eq. 41-42)."""
    image: PointerProperty(name="Target", type=bpy.types.Image, update=_changed,
                           description="The picture the design should tile with copies of itself")
    filepath: StringProperty(name="File", subtype='FILE_PATH', update=_target_file_changed,
                             description="Load the target picture from a file")
    window: FloatVectorProperty(name="Window", size=4, default=(0.0, 0.0, 1.0, 1.0), precision=3, update=_changed,
                                description="Where the picture lies in the plane: xmin, ymin, xmax, ymax")
    threshold: FloatProperty(name="Threshold", default=0.5, min=0.0, max=1.0, update=_changed,
                             description="Luminance splitting the shape from the background")
    raster: IntProperty(name="Raster", default=96, min=16, max=1024, update=_changed,
                        description="Pixels along the picture's long side for the collage distance (small: fast)")
    show: BoolProperty(name="Show target", default=True, update=_changed,
                       description="Draw the picture behind the preview and each map's copy of it")
    distance_pixels: FloatProperty(name="Collage distance (pixels)", default=-1.0)
    distance: FloatProperty(name="Collage distance", default=-1.0)
    bound: FloatProperty(name="Attractor within", default=-1.0)
    seconds: FloatProperty(name="Seconds", default=0.0)
    error: StringProperty(name="Error")


class IFSFORGE_PG_saved(PropertyGroup):
    """A system in the scene's library (for morphing and quick recall)."""
    name: StringProperty(name="Name")
    json: StringProperty(name="JSON")


class IFSFORGE_PG_scene(PropertyGroup):
    system: PointerProperty(type=IFSFORGE_PG_system)
    settings: PointerProperty(type=IFSFORGE_PG_settings)
    preview: PointerProperty(type=IFSFORGE_PG_preview)
    collage: PointerProperty(type=IFSFORGE_PG_collage)
    library: CollectionProperty(type=IFSFORGE_PG_saved)
    library_index: IntProperty(name="Saved system")
    morph_source: StringProperty(name="From", description="A saved system")
    morph_target: StringProperty(name="To", description="A saved system")
    cache_folder: StringProperty(
        name="Cache folder", subtype='DIR_PATH',
        description="Where generated files go. Empty: a folder next to the saved .blend, or the user cache")


classes = (IFSFORGE_PG_channel_row, IFSFORGE_PG_map, IFSFORGE_PG_morph, IFSFORGE_PG_system, IFSFORGE_PG_settings,
           IFSFORGE_PG_generated, IFSFORGE_PG_preview, IFSFORGE_PG_collage, IFSFORGE_PG_saved, IFSFORGE_PG_scene)


def register_pointers():
    bpy.types.Scene.ifsforge = PointerProperty(type=IFSFORGE_PG_scene)
    bpy.types.Object.ifsforge = PointerProperty(type=IFSFORGE_PG_generated)
    bpy.types.Image.ifsforge = PointerProperty(type=IFSFORGE_PG_generated)


def unregister_pointers():
    del bpy.types.Image.ifsforge
    del bpy.types.Object.ifsforge
    del bpy.types.Scene.ifsforge


# Records <-> properties ---------------------------------------------------------------------

def read_record(pg):
    """The codec record of a system PropertyGroup (plain Python values; compares with ==)."""
    morph = pg.morph
    try:
        layout = ifsforge.ChannelLayout(pg.layout)
        n, s = layout.dim, layout.spatial_dims
    except ifsforge.InputError:
        n = s = 2
    maps = []
    for m in pg.maps:
        coupling = tuple(m.coupling)
        maps.append({
            "translation": tuple(m.translation), "rotation": tuple(m.rotation), "scale": tuple(m.scale),
            "shear": tuple(m.shear), "reflect": tuple(m.reflect), "probability": m.probability,
            "channels": [tuple(row.coefficients)[:n] + (row.offset,) for row in m.channels],
            "coupling": [coupling[r * MAX_EXTRA:r * MAX_EXTRA + n - s] for r in range(s)],
        })
    return {
        "name": pg.name, "description": pg.description, "layout": pg.layout, "probabilities": pg.probabilities,
        "maps": maps,
        "morph": {"from": morph.source, "to": morph.target, "t": morph.factor} if morph.enabled else None,
    }


def write_record(pg, record):
    """Sets a system PropertyGroup from a codec record (the morph settings are kept)."""
    pg.name = record["name"]
    pg.description = record.get("description", "")
    pg.layout = record["layout"]
    pg.probabilities = record["probabilities"]
    pg.maps.clear()
    for i, m in enumerate(record["maps"]):
        write_map(pg.maps.add(), m, f"Map {i + 1}")
    pg.rows_layout = pg.layout
    pg.active_map = min(pg.active_map, len(pg.maps) - 1) if pg.maps else 0


def write_map(item, m, name=None):
    if name is not None:
        item.name = name
    item.translation = m["translation"]
    item.rotation = m["rotation"]
    item.scale = m["scale"]
    item.shear = m["shear"]
    item.reflect = m["reflect"]
    item.probability = m["probability"]
    item.channels.clear()
    for row in m["channels"]:
        r = item.channels.add()
        r.coefficients = (list(row[:-1]) + [0.0] * MAX_DIM)[:MAX_DIM]
        r.offset = row[-1]
    coupling = [0.0] * (3 * MAX_EXTRA)
    for r, values in enumerate(m["coupling"]):
        coupling[r * MAX_EXTRA:r * MAX_EXTRA + len(values)] = values
    item.coupling = coupling


MORPH_KEYS = ("enabled", "source", "target", "source_name", "target_name", "factor")


def snapshot_settings(settings_pg):
    """Plain values of a settings group (-0.0 written 0.0: equal values, equal digests)."""
    values = {}
    for prop in settings_pg.bl_rna.properties:
        if prop.identifier != "rna_type":
            value = getattr(settings_pg, prop.identifier)
            values[prop.identifier] = _plain(value if isinstance(value, (str, int, float, bool)) else tuple(value))
    return values


def _plain(value):
    if isinstance(value, float):
        return value + 0.0  # -0.0 + 0.0 is 0.0
    if isinstance(value, (tuple, list)):
        return tuple(_plain(v) for v in value)
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def snapshot_system(system_pg):
    """Plain values of a system group: {"record", "morph", "active_map"} (SYSTEM_KEYS)."""
    return {"record": _plain(read_record(system_pg) | {"morph": None}),
            "morph": {key: _plain(getattr(system_pg.morph, key)) for key in MORPH_KEYS},
            "active_map": system_pg.active_map}


SYSTEM_KEYS = ("record", "morph", "active_map")


def _single(value):
    """Values as a float property holds them (single precision)."""
    if isinstance(value, float):
        return float(np.float32(value)) + 0.0
    if isinstance(value, (tuple, list)):
        return tuple(_single(v) for v in value)
    if isinstance(value, dict):
        return {k: _single(v) for k, v in value.items()}
    return value


def system_values(record):
    """The snapshot_system() values of a codec record (no morph), as a system group would hold
    them: the datablock made from them stores them there, and its digest must not change."""
    return {"record": _single(record | {"morph": None}),
            "morph": {"enabled": False, "source": "", "target": "", "source_name": "", "target_name": "",
                      "factor": 0.0},
            "active_map": 0}


def snapshot(system_pg, settings_pg):
    """Plain values of a system and its settings (safe to keep while the UI changes them)."""
    return snapshot_system(system_pg) | {"settings": snapshot_settings(settings_pg)}


def restore(values, system_pg, settings_pg):
    """Sets a system and its settings from a snapshot() (the settings only when system_pg is None)."""
    if system_pg is not None:
        write_record(system_pg, values["record"])
        for key, value in values["morph"].items():
            setattr(system_pg.morph, key, value)
        system_pg.active_map = values["active_map"]
    for key, value in values["settings"].items():
        setattr(settings_pg, key, value)


def fit_channels(pg):
    """After a layout change, give every map the default rows of the new extra channels (a
    row's coefficients refer to the layout's dimensions, so old rows lose their meaning)."""
    try:
        layout = ifsforge.ChannelLayout(pg.layout)
    except ifsforge.InputError:
        return
    if pg.rows_layout == layout.text:
        return
    for i, m in enumerate(pg.maps):
        m.channels.clear()
        for row in codec.default_map(i, len(pg.maps), layout.text)["channels"]:
            r = m.channels.add()
            r.coefficients = (list(row[:-1]) + [0.0] * MAX_DIM)[:MAX_DIM]
            r.offset = row[-1]
        m.coupling = [0.0] * (3 * MAX_EXTRA)
    pg.rows_layout = layout.text
