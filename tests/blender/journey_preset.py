"""The artist's journey, step 3 (tests/python/test_blender_journey.py runs it): another fresh
Blender with a window (xvfb-run) and the installed add-on applies the user's operator preset the
way F9's preset menu does (Generate Volume once, then the preset on the last operation, redone)
and gets the same object as the one the preset was saved from.
    xvfb-run blender --python tests/blender/journey_preset.py -- --preset FILE --expect JSON"""
import argparse
import json
import sys
from pathlib import Path

import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
parser = argparse.ArgumentParser()
parser.add_argument("--preset", required=True)
parser.add_argument("--expect", required=True, help="JSON: the file name, summary and rotation of the original")
args = parser.parse_args(argv)
expect = json.loads(args.expect)
bpy.context.preferences.view.show_splash = False
checks = Checks()


def override():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    region = next(r for r in area.regions if r.type == 'WINDOW')
    return bpy.context.temp_override(window=window, area=area, region=region)


def preset_recreates_the_object():
    scene = bpy.context.scene
    assert len(scene.ifsforge.system.maps) == 0  # a fresh scene: the preset must bring the system
    scene.ifsforge.settings.volume_resolution = 12  # a quick first run (its values are replaced)
    for obj in bpy.context.selected_objects:
        obj.select_set(False)
    with override():
        assert bpy.ops.ifsforge.generate_volume('EXEC_DEFAULT', True) == {'FINISHED'}
        assert bpy.context.active_operator.bl_idname == "IFSFORGE_OT_generate_volume"
        assert bpy.ops.script.execute_preset(filepath=args.preset, menu_idname="WM_MT_operator_presets") \
            == {'FINISHED'}
        assert bpy.ops.ed.undo_redo() == {'FINISHED'}
    obj = bpy.context.active_object
    assert len([o for o in bpy.data.objects if o.type == 'VOLUME']) == 1  # redone, not added
    got = {"file": Path(obj.data.filepath).name, "summary": obj.ifsforge.summary,
           "rotation": obj.ifsforge.system.maps[0].rotation[2]}
    checks.values["recreated"] = got
    assert got == expect, (got, expect)


def tick():
    checks.run("preset_recreates_the_object", preset_recreates_the_object)
    checks.finish()


bpy.app.timers.register(tick, first_interval=1.0)
