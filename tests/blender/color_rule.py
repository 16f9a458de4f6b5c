"""Inside Blender: one colour, whatever the path. DIR/colour.json (written by
tests/python/test_axes_color.py) names a system whose attractor has the display colour
"display" wherever x < 0.45 and y < 0.45, and the files the CLI wrote from it. Blender must
see that colour (linear inside Blender: srgb_to_linear of it; compared back in display values,
within 1/255) in the add-on's iso-surface and instance attributes, and in what its own
importers make of the CLI's iso .glb (COLOR_0), iso .ply (8-bit vertex colours) and instance
.glb (baseColorFactor). The add-on's .vdb path is reported for pyopenvdb to check.

    blender -b --factory-startup --python color_rule.py -- --python-path BUILD/python --out DIR"""
import json
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon  # noqa: E402

# Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed.
if "bool" not in np.__dict__:
    np.bool = bool

args = arguments()
OUT = Path(args.out)
enable_addon(args.python_path)

import ifsforge  # noqa: E402

checks = Checks()
context = bpy.context
with open(OUT / "colour.json") as f:
    task = json.load(f)
DISPLAY = np.array(task["display"])


def same_color(linear, what):
    """Linear RGB rows (Blender's values) against the display colour, compared as display values."""
    linear = np.asarray(linear, float).reshape(-1, 3)
    assert len(linear) > 0, f"{what}: no sample in the corner"
    display = ifsforge.linear_to_srgb(linear)
    error = np.abs(display - DISPLAY).max()
    checks.values[f"{what}_max_error_255"] = float(error * 255)
    close(display, np.broadcast_to(DISPLAY, display.shape), 1 / 255)


def corner(points):
    return (points[:, 0] < 0.45) & (points[:, 1] < 0.45)


def corner_of_bounds(points):
    """corner() in the frame of the points' own box: the add-on puts an object's origin at the
    centre of its bounds, so its local coordinates are the system's shifted."""
    lo, hi = points.min(axis=0), points.max(axis=0)
    return corner((points - lo) / np.maximum(hi - lo, 1e-12))


def attribute_by_vertex(mesh, attribute):
    """(vertex positions, linear RGB) of a colour attribute on points or face corners."""
    values = np.empty(4 * len(attribute.data), np.float32)
    attribute.data.foreach_get("color", values)
    values = values.reshape(-1, 4)[:, :3]
    co = np.empty(3 * len(mesh.vertices), np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    if attribute.domain == 'CORNER':
        index = np.empty(len(mesh.loops), np.int32)
        mesh.loops.foreach_get("vertex_index", index)
        co = co[index]
    return co, values


def generate(kind):
    for obj in context.selected_objects:
        obj.select_set(False)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def addon():
    bpy.ops.ifsforge.import_system(filepath=task["system"])
    settings = context.scene.ifsforge.settings
    context.scene.ifsforge.cache_folder = str(OUT / "cache")
    settings.volume_resolution, settings.mesh_iso, settings.mesh_adaptivity = 32, 0.5, 0.0
    mesh = generate("mesh").data
    co, colours = attribute_by_vertex(mesh, mesh.attributes["ifs_color"])
    same_color(colours[corner_of_bounds(co)], "addon_iso")
    settings.instance_depth, settings.instance_color_by = 2, 'channels'
    points = generate("instances").data
    co, colours = attribute_by_vertex(points, points.attributes["ifs_color"])
    same_color(colours[corner_of_bounds(co)], "addon_instances")
    settings.volume_density = 'binary'
    volume = generate("volume")
    checks.values["addon_vdb"] = bpy.path.abspath(volume.data.filepath)


def imported_mesh(path, importer):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    importer(filepath=path)
    meshes = [o for o in context.scene.objects if o.type == 'MESH']
    assert len(meshes) == 1, f"{len(meshes)} mesh objects"
    mesh = meshes[0].data
    assert len(mesh.color_attributes) == 1, f"colour attributes: {[a.name for a in mesh.color_attributes]}"
    co, colours = attribute_by_vertex(mesh, mesh.color_attributes[0])
    world = np.array(meshes[0].matrix_world)
    return co @ world[:3, :3].T + world[:3, 3], colours


def iso_glb():
    co, colours = imported_mesh(task["iso_glb"], bpy.ops.import_scene.gltf)
    same_color(colours[corner(co)], "iso_glb")


def iso_ply():
    co, colours = imported_mesh(task["iso_ply"], bpy.ops.import_mesh.ply)
    same_color(colours[corner(co)], "iso_ply")


def instances_glb():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=task["instances_glb"])
    context.view_layer.update()
    colours = []
    for obj in context.scene.objects:
        if obj.type != 'MESH' or not corner(np.array([obj.matrix_world.translation]))[0]:
            continue
        shader = next(n for n in obj.active_material.node_tree.nodes if n.type == 'BSDF_PRINCIPLED')
        colours.append(list(shader.inputs["Base Color"].default_value)[:3])
    same_color(colours, "instances_glb")


checks.run("addon", addon)
checks.run("iso_glb", iso_glb)
checks.run("iso_ply", iso_ply)
checks.run("instances_glb", instances_glb)
checks.finish()
