"""The artist's journey, step 1 (tests/python/test_blender_journey.py runs it): Edit >
Preferences > Add-ons > Install of the add-on's zip in a Blender whose user folders are empty and
where no other `ifsforge` module is importable, then enable it and save the preferences.
    blender -b --python tests/blender/journey_install.py -- --zip ZIP --out DIR"""
import argparse
import os
import sys
from pathlib import Path

import addon_utils
import bpy

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
parser = argparse.ArgumentParser()
parser.add_argument("--zip", required=True)
parser.add_argument("--out", required=True)
args = parser.parse_args(argv)
checks = Checks()
user_addons = Path(bpy.utils.user_resource('SCRIPTS', path="addons"))


def empty_user_folders():
    scripts = Path(bpy.utils.user_resource('SCRIPTS'))
    assert scripts == Path(os.environ["BLENDER_USER_SCRIPTS"]), scripts
    assert not any(scripts.rglob("*")), sorted(scripts.rglob("*"))
    assert not any(Path(os.environ["BLENDER_USER_CONFIG"]).rglob("*"))
    assert "ifsforge" not in sys.modules and "ifsforge_addon" not in addon_utils.addons_fake_modules
    try:  # nothing of the system's: the zip must bring the module
        import ifsforge  # noqa: F401
    except ImportError:
        return
    raise AssertionError(f"an ifsforge module is importable before the install: {sys.modules['ifsforge'].__file__}")


def install_and_enable():
    assert bpy.ops.preferences.addon_install(filepath=args.zip) == {'FINISHED'}
    assert (user_addons / "ifsforge_addon" / "__init__.py").is_file()
    assert bpy.ops.preferences.addon_enable(module="ifsforge_addon") == {'FINISHED'}
    assert addon_utils.check("ifsforge_addon") == (True, True)
    import ifsforge
    module = Path(ifsforge.__file__).resolve()
    assert module.is_relative_to(user_addons.resolve() / "ifsforge_addon"), module
    checks.values["module"] = str(module)
    checks.values["compiled"] = sorted(p.name for p in module.parent.glob("_*.so"))
    assert hasattr(bpy.types, "IFSFORGE_OT_generate_volume")
    Path(os.environ["BLENDER_USER_CONFIG"]).mkdir(parents=True, exist_ok=True)
    assert bpy.ops.wm.save_userpref() == {'FINISHED'}


checks.run("empty_user_folders", empty_user_folders)
checks.run("install_and_enable", install_and_enable)
checks.finish()
