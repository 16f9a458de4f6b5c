"""Imports a terrain .glb in Blender (headless) and checks what ifsforge promised about it.

blender -b --factory-startup --python-exit-code 1 --python terrain_glb_import.py -- \
    TERRAIN.glb VERTICES TRIANGLES TEXTURE_WIDTH SIZE_X SIZE_Y HEIGHT_RANGE

Checks: one mesh with exactly VERTICES vertices and TRIANGLES triangles; its material's Base
Color comes from an image texture TEXTURE_WIDTH x 1 (the palette strip); the glTF y-up terrain
lands z-up in Blender, spanning SIZE_X x SIZE_Y horizontally and HEIGHT_RANGE vertically.
Prints one line starting with OK, or raises (the exit code is then 1).
"""
import sys

import bpy
import numpy

# Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed.
if "bool" not in numpy.__dict__:
    numpy.bool = bool


def main(argv):
    path = argv[0]
    vertices, triangles, texture_width = (int(v) for v in argv[1:4])
    size_x, size_y, height_range = (float(v) for v in argv[4:7])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    assert len(meshes) == 1, f"expected one mesh object, found {len(meshes)}"
    mesh = meshes[0].data
    assert len(mesh.vertices) == vertices, f"{len(mesh.vertices)} vertices, expected {vertices}"
    mesh.calc_loop_triangles()
    assert len(mesh.loop_triangles) == triangles, f"{len(mesh.loop_triangles)} triangles, expected {triangles}"

    material = mesh.materials[0]
    bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    links = bsdf.inputs["Base Color"].links
    assert links, "Base Color is not linked to a texture"
    node = links[0].from_node
    while node.type != "TEX_IMAGE":  # the importer may put a colour/UV node in between
        node = next(l.from_node for i in node.inputs for l in i.links)
    width, height = node.image.size
    assert (width, height) == (texture_width, 1), f"texture {width}x{height}, expected {texture_width}x1"

    xs = [v.co.x for v in mesh.vertices]
    ys = [v.co.y for v in mesh.vertices]
    zs = [v.co.z for v in mesh.vertices]
    extent = (max(xs) - min(xs), max(ys) - min(ys), max(zs) - min(zs))
    for got, want, axis in zip(extent, (size_x, size_y, height_range), "xyz"):
        assert abs(got - want) <= 1e-4 * max(1.0, want), f"{axis} extent {got}, expected {want}"
    print(f"OK {len(mesh.vertices)} vertices, {len(mesh.loop_triangles)} triangles, "
          f"texture {width}x{height}, extent {extent[0]:.4f} x {extent[1]:.4f} x {extent[2]:.4f}")


main(sys.argv[sys.argv.index("--") + 1:])
