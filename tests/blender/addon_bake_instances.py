"""Inside Blender: Bake Animation of an instances object whose system is keyframed keeps each
frame's point cloud (positions and instance attributes) in the .blend; a second Blender without
the add-on or the ifsforge module places the same instances at every baked frame."""
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon, open_without_ifsforge  # noqa: E402

args = arguments()
OUT = Path(args.out) / "bake_instances"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

checks = Checks()
context = bpy.context

# Every instance the object makes at the current frame: its world matrix, rows sorted (order-free).
PLACED = """
def placed(bpy, name):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    rows = [[v for row in inst.matrix_world for v in row] for inst in depsgraph.object_instances
            if inst.is_instance and inst.parent and inst.parent.original.name == name]
    return sorted(rows)
"""
exec(PLACED)

PROBE = PLACED + """
import bpy, sys
scene = bpy.context.scene
out["frames"] = {}
for frame in (1, 2):
    scene.frame_set(frame)
    out["frames"][frame] = placed(bpy, sys.argv[-1])
"""


def baked_instances_play_without_the_addon():
    for obj in list(bpy.data.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    bpy.ops.wm.save_as_mainfile(filepath=str(OUT / "scene.blend"))
    scene = context.scene
    scene.frame_set(1)
    bpy.ops.ifsforge.load_preset(preset="menger_sponge.json")
    scene.ifsforge.settings.instance_depth = 2
    bpy.ops.ifsforge.generate_instances()
    owner = context.active_object
    item = owner.ifsforge.system.maps[0]
    item.keyframe_insert("scale", frame=1)
    item.scale = (0.2, 0.2, 0.2)
    item.keyframe_insert("scale", frame=2)
    expected = {}
    for frame in (1, 2):
        scene.frame_set(frame)
        expected[frame] = placed(bpy, owner.name)
    assert len(expected[1]) == len(expected[2]) == 400, (len(expected[1]), len(expected[2]))
    assert np.abs(np.subtract(expected[1], expected[2])).max() > 1e-3, "the keyframed scale should move instances"
    assert bpy.ops.ifsforge.bake_animation(frame_start=1, frame_end=2) == {'FINISHED'}
    assert owner.ifsforge.baked and owner.modifiers[0].name == "ifsforge bake"
    for frame in (2, 1):  # the baked object plays the frames here too
        scene.frame_set(frame)
        close(placed(bpy, owner.name), expected[frame], 1e-5)
    bpy.ops.wm.save_mainfile()
    seen = open_without_ifsforge(OUT / "scene.blend", PROBE, [owner.name], OUT)
    for frame in (1, 2):
        close(seen["frames"][str(frame)], expected[frame], 1e-5)


checks.run("baked_instances_play_without_the_addon", baked_instances_play_without_the_addon)
checks.finish()
