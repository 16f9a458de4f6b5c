"""Inside Blender: every mesh file ifsforge writes stands upright after an import with the
importer's default settings (glTF y up, OBJ forward -Z / up Y, PLY as it is).

    blender -b --factory-startup --python mesh_axes_import.py -- --python-path BUILD/python --out DIR

DIR/axes.json (written by tests/python/test_axes_color.py) lists the files and what each
must look like in Blender's z-up world: "box" (the world bounding box, within "tolerance"),
"top" (the x, y of the highest vertex, within "top_tolerance"), or "nodes" (instance name ->
world translation). One CHECK line per file (see addon_harness.py)."""
import json
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments  # noqa: E402

# Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed.
if "bool" not in np.__dict__:
    np.bool = bool

IMPORTERS = {
    ".glb": lambda path: bpy.ops.import_scene.gltf(filepath=path),
    ".obj": lambda path: bpy.ops.wm.obj_import(filepath=path),  # File > Import > Wavefront (.obj)
    ".ply": lambda path: bpy.ops.import_mesh.ply(filepath=path),
}


def world_vertices(objects):
    """Every vertex of the mesh objects, in world coordinates."""
    out = []
    for obj in objects:
        co = np.empty(3 * len(obj.data.vertices), np.float32)
        obj.data.vertices.foreach_get("co", co)
        matrix = np.array(obj.matrix_world)
        out.append(co.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3])
    return np.concatenate(out)


def check_file(entry):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    path = entry["path"]
    IMPORTERS[Path(path).suffix](path)
    bpy.context.view_layer.update()
    meshes = [o for o in bpy.context.scene.objects if o.type == 'MESH']
    assert meshes, "nothing imported"
    if "nodes" in entry:
        for name, position in entry["nodes"].items():
            world = np.array(bpy.data.objects[name].matrix_world.translation)
            assert np.allclose(world, position, atol=1e-4), f"instance {name} at {world}, expected {position}"
        return
    points = world_vertices(meshes)
    lo, hi = points.min(axis=0), points.max(axis=0)
    box = np.array(entry["box"])
    tolerance = entry["tolerance"]
    assert np.allclose(lo, box[:3], atol=tolerance) and np.allclose(hi, box[3:], atol=tolerance), \
        f"world box {lo.round(4).tolist()} .. {hi.round(4).tolist()}, expected {box.round(4).tolist()}"
    top = points[np.argmax(points[:, 2])]
    assert np.allclose(top[:2], entry["top"], atol=entry["top_tolerance"]), \
        f"the highest vertex is at {top.round(4).tolist()}, expected above {entry['top']}"


args = arguments()
checks = Checks()
with open(Path(args.out) / "axes.json") as f:
    files = json.load(f)
for entry in files:
    checks.run(Path(entry["path"]).name, check_file, entry)
checks.finish()
