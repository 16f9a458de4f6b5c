"""Inside Blender: Bake Animation of an instances object whose system is keyframed keeps each
frame's point cloud (positions and instance attributes) in the .blend; a second Blender without
the add-on or the ifsforge module places the same instances at every baked frame."""
import json
import os
import subprocess
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon  # noqa: E402

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
import bpy, json, importlib.util, sys
scene = bpy.context.scene
out = {"module": importlib.util.find_spec("ifsforge") is not None,
       "addon": "ifsforge_addon" in bpy.context.preferences.addons, "frames": {}}
for frame in (1, 2):
    scene.frame_set(frame)
    out["frames"][frame] = placed(bpy, sys.argv[-1])
print("PROBE " + json.dumps(out))
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
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    probe = OUT / "probe.py"
    probe.write_text(PROBE)
    result = subprocess.run([bpy.app.binary_path, "-b", "--factory-startup", str(OUT / "scene.blend"),
                             "--python", str(probe), "--", owner.name],
                            capture_output=True, text=True, timeout=300, env=env)
    lines = [line for line in result.stdout.splitlines() if line.startswith("PROBE ")]
    assert lines, result.stdout[-3000:] + result.stderr[-3000:]
    seen = json.loads(lines[0][len("PROBE "):])
    assert not seen["module"] and not seen["addon"], seen
    for frame in (1, 2):
        close(seen["frames"][str(frame)], expected[frame], 1e-5)


checks.run("baked_instances_play_without_the_addon", baked_instances_play_without_the_addon)
checks.finish()
