"""Inside Blender: File > Export > POV-Ray scene writes the scene's ifsforge objects through the
active camera; the real POV-Ray's render of it and Blender's own render of the scene cover the
same pixels (silhouette IoU >= 0.85), so positions, camera axes, field of view and handedness
agree."""
import sys
from pathlib import Path

import bpy
import numpy as np
from mathutils import Euler, Vector

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, enable_addon, expect_report  # noqa: E402

args = arguments()
OUT = Path(args.out) / "povray"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

checks = Checks()
context = bpy.context
WIDTH, HEIGHT = 160, 112


def generate(kind, preset, **values):
    for obj in context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset=preset)
    for name, value in values.items():
        setattr(context.scene.ifsforge.settings, name, value)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def iou(a, b):
    return (a & b).sum() / max((a | b).sum(), 1)


def silhouettes():
    scene = context.scene
    # The world's colour is POV-Ray's background: one no object here shows.
    background = next(n for n in scene.world.node_tree.nodes if n.type == 'BACKGROUND')
    background.inputs["Color"].default_value = (1.0, 0.0, 1.0, 1.0)
    expect_report(lambda: bpy.ops.ifsforge.export_povray_scene(filepath=str(OUT / "none.pov")), "no terrain")
    assert not (OUT / "none.pov").exists()
    for obj in list(scene.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    sponge = generate("instances", "menger_sponge.json", instance_depth=2)
    sponge.location, sponge.rotation_euler = (-1.6, 0.4, 0.2), (0.0, 0.0, 0.5)
    terrain = generate("terrain", "barnsley_fern.json", terrain_source='RANDOM', terrain_grid='regular',
                       terrain_resolution=33, terrain_size=3.0, terrain_height=1.0)
    terrain.location = (1.2, -0.5, -0.4)
    # An asymmetric scene seen from an unusual direction with a roll: a mirror or a swapped axis
    # anywhere in the camera's conversion moves the silhouettes apart.
    camera = scene.camera
    camera.location = (3.0, -7.0, 4.5)
    camera.rotation_euler = (-camera.location).to_track_quat('-Z', 'Y').to_euler()
    camera.matrix_world = camera.matrix_world @ Euler((0.0, 0.0, 0.35)).to_matrix().to_4x4()
    camera.data.type, camera.data.lens = 'PERSP', 40
    context.view_layer.update()
    r = scene.render
    r.engine = 'BLENDER_WORKBENCH'
    r.resolution_x, r.resolution_y, r.resolution_percentage = WIDTH, HEIGHT, 100
    r.film_transparent = True
    r.image_settings.file_format, r.image_settings.color_mode = 'PNG', 'RGBA'
    r.filepath = str(OUT / "blender.png")
    bpy.ops.render.render(write_still=True)
    blender = load(OUT / "blender.png")[:, :, 3] > 0.5

    result = bpy.ops.ifsforge.export_povray_scene(filepath=str(OUT / "scene.pov"), render=True)
    assert result == {'FINISHED'}, result
    text = (OUT / "scene.pov").read_text()
    assert text.count("union {") == 1 and text.count("mesh2 {") == 2 and "camera {" in text, text[:400]
    pov = load(OUT / "scene.png")[:, :, :3]
    povray = np.abs(pov - world_srgb()).max(axis=2) > 0.25  # not the world's colour, POV-Ray's background
    overlap = iou(blender, povray)
    checks.values["silhouette_iou"] = float(overlap)
    assert 0.08 < blender.mean() < 0.8 and 0.08 < povray.mean() < 0.8, (blender.mean(), povray.mean())
    assert overlap >= 0.85, overlap
    assert iou(blender, povray[:, ::-1]) < 0.7 and iou(blender, povray[::-1]) < 0.7  # not symmetric


def world_srgb():
    """The scene's world colour as the PNG holds it (sRGB)."""
    background = next(n for n in context.scene.world.node_tree.nodes if n.type == 'BACKGROUND')
    linear = np.array(background.inputs["Color"].default_value[:3]) * background.inputs["Strength"].default_value
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)


def load(path):
    image = bpy.data.images.load(str(path), check_existing=False)
    pixels = np.array(image.pixels[:], np.float32).reshape(image.size[1], image.size[0], 4)
    bpy.data.images.remove(image)
    return pixels


def volume_media():
    """A volume becomes media reading a .df3 of its grid; POV-Ray changes the background there."""
    for obj in list(context.scene.objects):
        if obj.type in ('MESH', 'VOLUME'):
            bpy.data.objects.remove(obj)
    volume = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=16)
    volume.location = (0.0, 0.0, 0.0)
    camera = context.scene.camera
    camera.location = (0.5, -3.5, 2.0)
    camera.rotation_euler = (Vector((0.5, 0.5, 0.4)) - camera.location).to_track_quat('-Z', 'Y').to_euler()
    assert bpy.ops.ifsforge.export_povray_scene(filepath=str(OUT / "volume.pov"), render=True) == {'FINISHED'}
    df3 = sorted(OUT.glob("volume_*.df3"))
    assert len(df3) == 1, df3
    sizes = np.frombuffer(df3[0].read_bytes()[:6], ">u2") - 2  # an empty voxel around the grid
    assert "x".join(str(n) for n in sizes) in volume.ifsforge.summary, (sizes, volume.ifsforge.summary)
    assert "density_file df3" in (OUT / "volume.pov").read_text()
    pov = load(OUT / "volume.png")[:, :, :3]
    covered = (np.abs(pov - world_srgb()).max(axis=2) > 0.1).mean()
    checks.values["volume_coverage"] = float(covered)
    assert 0.02 < covered < 0.9, covered


checks.run("silhouettes", silhouettes)
checks.run("volume_media", volume_media)
checks.finish()
