"""Inside Blender: generated objects follow their stored values whatever animates them (driver,
NLA strip, script), and Bake Animation turns the frames into files Blender reads natively: a
second Blender without the add-on or the ifsforge module plays and renders the baked frames."""
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon, open_without_ifsforge, render_alpha  # noqa: E402

args = arguments()
OUT = Path(args.out) / "animation"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

checks = Checks()
context = bpy.context


def generate(kind, preset, **values):
    for obj in context.selected_objects:
        obj.select_set(False)
    bpy.ops.ifsforge.load_preset(preset=preset)
    for name, value in values.items():
        setattr(context.scene.ifsforge.settings, name, value)
    getattr(bpy.ops.ifsforge, f"generate_{kind}")()
    return context.active_object


def dims(obj):
    """The voxel box of a generated volume, from its summary ("... voxels in 16x16x16 (prr)...")."""
    return obj.ifsforge.summary.split(" in ")[1].split(" ")[0]


def driver_nla_and_script():
    context.scene.ifsforge.cache_folder = str(OUT / "cache")
    context.scene.frame_set(1)
    # A driver on a map's scale.
    driven = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=16)
    curve = driven.ifsforge.system.maps[0].driver_add("scale", 0)
    curve.driver.expression = "0.5 - 0.1 * frame"
    context.scene.frame_set(2)
    first = driven.data.filepath
    context.scene.frame_set(3)
    assert driven.data.filepath != first and Path(bpy.path.abspath(driven.data.filepath)).is_file()
    close(driven.evaluated_get(context.evaluated_depsgraph_get()).ifsforge.system.maps[0].scale[0], 0.2, 1e-6)
    # An NLA strip (no active action) animating the resolution.
    stripped = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=16)
    settings = stripped.ifsforge.settings
    settings.volume_resolution = 16
    settings.keyframe_insert("volume_resolution", frame=1)
    settings.volume_resolution = 24
    settings.keyframe_insert("volume_resolution", frame=5)
    data = stripped.animation_data
    action, data.action = data.action, None
    data.nla_tracks.new().strips.new("resolution", 1, action)
    context.scene.frame_set(5)
    assert dims(stripped).count("24") >= 1 and "16" not in dims(stripped), stripped.ifsforge.summary
    context.scene.frame_set(1)
    assert "24" not in dims(stripped), stripped.ifsforge.summary
    # A script changes a stored value: the next frame rebuilds.
    driven.animation_data_clear()
    driven.ifsforge.settings.volume_resolution = 20
    context.scene.frame_set(2)
    assert "20" in dims(driven), driven.ifsforge.summary
    for obj in (driven, stripped):
        bpy.data.objects.remove(obj)


PROBE = """
import bpy, sys
scene = bpy.context.scene
out["frames"] = {}
for frame in (1, 2):
    scene.frame_set(frame)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    terrain = bpy.data.objects[sys.argv[-2]].evaluated_get(depsgraph)
    volume = bpy.data.objects[sys.argv[-1]].evaluated_get(depsgraph)
    volume.data.grids.load()
    out["frames"][frame] = {"z": [v.co.z for v in terrain.data.vertices],
                            "vdb": volume.data.grids.frame_filepath, "grids": [g.name for g in volume.data.grids]}
scene.frame_set(2)
scene.render.filepath = sys.argv[-3]
bpy.ops.render.render(write_still=True)
"""


def bake_renders_without_the_addon():
    bpy.ops.wm.read_homefile(use_empty=False)
    for obj in list(bpy.data.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    folder = OUT / "baked"
    folder.mkdir(exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=str(folder / "scene.blend"))
    scene = context.scene
    scene.frame_set(1)
    terrain = generate("terrain", "barnsley_fern.json", terrain_source='RANDOM', terrain_resolution=17, seed=0)
    terrain.ifsforge.settings.keyframe_insert("seed", frame=1)
    terrain.ifsforge.settings.seed = 7
    terrain.ifsforge.settings.keyframe_insert("seed", frame=2)
    volume = generate("volume", "sierpinski_tetrahedron.json", volume_resolution=16)
    item = volume.ifsforge.system.maps[0]
    item.keyframe_insert("scale", frame=1)
    item.scale = (0.25, 0.25, 0.25)
    item.keyframe_insert("scale", frame=2)
    expected = {}
    for frame in (1, 2):
        scene.frame_set(frame)
        expected[frame] = [v.co.z for v in terrain.data.vertices]
    assert np.abs(np.subtract(expected[1], expected[2])).max() > 1e-3, "the seed should change the heights"
    render_alpha(terrain, OUT / "setup.png", size=24, samples=2)  # camera, engine and film for the probe
    for obj in (terrain, volume):
        obj.hide_render = False
    assert bpy.ops.ifsforge.bake_animation(frame_start=1, frame_end=2) == {'FINISHED'}
    assert terrain.ifsforge.baked and volume.ifsforge.baked and volume.data.is_sequence
    assert volume.data.filepath.startswith("//scene_ifsforge/bake/"), volume.data.filepath
    bpy.ops.wm.save_mainfile()
    # Another Blender: factory settings, the add-on and the ifsforge module hidden.
    seen = open_without_ifsforge(folder / "scene.blend", PROBE,
                                 [OUT / "baked_frame2.png", terrain.name, volume.name], OUT)
    for frame in (1, 2):
        close(seen["frames"][str(frame)]["z"], expected[frame], 1e-5)
        assert seen["frames"][str(frame)]["vdb"].endswith(f"_{frame:04d}.vdb"), seen["frames"][str(frame)]["vdb"]
        assert seen["frames"][str(frame)]["grids"] == ["density"]
    image = bpy.data.images.load(str(OUT / "baked_frame2.png"))
    alpha = np.array(image.pixels[:])[3::4]
    assert alpha.max() > 0.5 and alpha.min() < 0.01, (alpha.min(), alpha.max())


checks.run("driver_nla_and_script", driver_nla_and_script)
checks.run("bake_renders_without_the_addon", bake_renders_without_the_addon)
checks.finish()
