"""Blender check of ifsforge's instanced glTF: import FILE.glb with Blender's own importer and
compare with EXPECTED.json (written by tests/python/test_vector.py):
    blender -b --factory-startup --python-exit-code 1 --python vector_gltf_import.py -- FILE.glb EXPECTED.json
Checks: one object per instance under the root, objects of one glTF mesh share one Blender
mesh (linked duplicates), the world positions, and the address custom property."""
import json
import sys

import bpy
import numpy

# Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool


def main(argv):
    glb, expected_path = argv
    with open(expected_path) as f:
        expected = json.load(f)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=glb)
    root = bpy.data.objects[expected["root"]]
    children = [o for o in root.children if o.type == "MESH"]
    assert len(children) == expected["count"], f"{len(children)} instance objects, expected {expected['count']}"
    meshes = {o.data.name for o in children}
    assert len(meshes) == expected["meshes"], f"{len(meshes)} mesh datablocks, expected {expected['meshes']}"
    users = sorted(m.users for m in bpy.data.meshes)
    assert sum(users) >= expected["count"], f"mesh users {users}"
    bpy.context.view_layer.update()
    for name, position in expected["positions"].items():
        obj = bpy.data.objects[name]
        world = obj.matrix_world.translation
        assert all(abs(world[c] - position[c]) < 1e-4 for c in range(3)), f"{name}: {tuple(world)} != {position}"
        assert obj["address"] == name, f"{name}: custom property address = {obj['address']}"
        scale = obj.matrix_world.to_scale()
        assert abs(scale[0] - expected["scales"][name]) < 1e-5, f"{name}: scale {tuple(scale)}"
    print(f"VECTOR_GLTF_OK {len(children)} objects sharing {len(meshes)} meshes")


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:])
