"""Imports an ifsforge .vdb in Blender (headless) and checks what ifsforge promised about it.

blender -b --factory-startup --python-exit-code 1 --python volume_import.py -- \
    VOLUME.vdb VOXEL XMIN YMIN ZMIN XMAX YMAX ZMAX [RED GREEN BLUE]

Checks: the file imports as one Volume object whose grids are 'density' (float) and 'color'
(vector); the object's bounding box is the world box of the occupied voxels (the attractor sits
where the IFS puts it: XMIN..ZMAX, the box of the occupied voxels, to within VOXEL). With RED GREEN BLUE (the volume's constant colour),
a 48x48 Cycles render through a Principled Volume that reads 'density' and 'color' must show
the volume tinted by that colour. Prints one line starting with OK, or raises (exit code 1).
"""
import os
import sys

import bpy
from mathutils import Vector


def render_mean_color(obj, box):
    """Renders the volume alone, lit by a white world, and returns the mean RGB of the pixels
    it covers (those brighter than the empty background)."""
    material = bpy.data.materials.new("ifsforge_volume")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    volume = nodes.new("ShaderNodeVolumePrincipled")
    volume.inputs["Density Attribute"].default_value = "density"
    volume.inputs["Color Attribute"].default_value = "color"
    volume.inputs["Density"].default_value = 40.0
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(volume.outputs["Volume"], output.inputs["Volume"])
    obj.data.materials.append(material)

    scene = bpy.context.scene
    world = bpy.data.worlds.new("white")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world
    centre = [(box[a] + box[a + 3]) / 2 for a in range(3)]
    size = max(box[a + 3] - box[a] for a in range(3))
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 1.2 * size
    camera.location = (centre[0], centre[1], centre[2] + 3 * size)
    scene.collection.objects.link(camera)
    scene.camera = camera
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
    scene.render.resolution_x = scene.render.resolution_y = 48
    scene.render.film_transparent = True
    path = os.path.join(bpy.app.tempdir, "ifsforge_volume_render.png")
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    pixels = list(image.pixels)
    covered = [pixels[i:i + 4] for i in range(0, len(pixels), 4) if pixels[i + 3] > 0.2]
    assert covered, "the render shows nothing where the volume is"
    return [sum(p[c] for p in covered) / len(covered) for c in range(3)], len(covered)


def main(argv):
    path = os.path.abspath(argv[0])
    voxel = float(argv[1])
    box = [float(v) for v in argv[2:8]]
    color = [float(v) for v in argv[8:11]] if len(argv) >= 11 else None
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.object.volume_import(filepath=path, directory=os.path.dirname(path),
                                 files=[{"name": os.path.basename(path)}])
    volumes = [o for o in bpy.context.scene.objects if o.type == "VOLUME"]
    assert len(volumes) == 1, f"expected one volume object, found {len(volumes)}"
    obj = volumes[0]
    grids = obj.data.grids
    assert grids.load(), f"Blender could not load the grids: {grids.error_message}"
    types = {g.name: g.data_type for g in grids}
    assert types.get("density") == "FLOAT", f"density grid: {types}"
    assert types.get("color") == "VECTOR_FLOAT", f"color grid: {types}"

    corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    lo = [min(c[a] for c in corners) for a in range(3)]
    hi = [max(c[a] for c in corners) for a in range(3)]
    tolerance = 1.01 * voxel
    for a, axis in enumerate("xyz"):
        assert abs(lo[a] - box[a]) <= tolerance and abs(hi[a] - box[a + 3]) <= tolerance, \
            f"{axis}: Blender's bounds [{lo[a]:.4f}, {hi[a]:.4f}], expected [{box[a]:.4f}, {box[a + 3]:.4f}]"
    message = f"OK grids {sorted(types)}, bounds {[round(v, 4) for v in lo + hi]}"
    if color:
        mean, covered = render_mean_color(obj, box)
        strongest = max(range(3), key=lambda c: color[c])
        weakest = min(range(3), key=lambda c: color[c])
        assert mean[strongest] > 1.5 * mean[weakest] + 0.02, \
            f"rendered colour {mean} is not tinted like the volume's {colour}"
        message += f", render {covered} px mean RGB {[round(v, 3) for v in mean]}"
    print(message)


main(sys.argv[sys.argv.index("--") + 1:])
