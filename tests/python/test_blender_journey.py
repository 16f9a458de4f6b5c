"""The artist's first hour in real Blender, as one journey: the add-on's zip (package.sh) installed
with Edit > Preferences > Add-ons > Install into empty user folders, with no other ifsforge module
importable (tests/blender/journey_install.py); a fresh scene where every Shift+A > IFS entry works,
saved, undone and redone (journey_scene.py, with a window under xvfb-run: menus are drawn); the
user's preset applied in another fresh Blender (journey_preset.py); and the .blend opened and
rendered by a Blender without the add-on, nothing missing."""
import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from conftest import BUILD_PYTHON, ROOT, run_group, xvfb_run

BLENDER = shutil.which("blender")
pytestmark = pytest.mark.skipif(BLENDER is None, reason="needs Blender")
SYSTEM_MODULE = Path("/usr/local/lib/python3.11/dist-packages/ifsforge")
WINDOW = "960x600"  # the X screen, and so Blender's window (see the scene step)

# Imported first by Blender's Python (site): every sys.path entry holding an ifsforge package
# (the system-wide install of the README's set-up, a build tree) is dropped, so only the add-on's
# own copy can be found.
HIDE = """import os, sys
sys.path[:] = [p for p in sys.path if not os.path.isdir(os.path.join(p or '.', 'ifsforge'))]
"""


def blender_env(tmp_path):
    hide = tmp_path / "hide"
    hide.mkdir(exist_ok=True)
    (hide / "sitecustomize.py").write_text(HIDE)
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PYTHON", "BLENDER_"))}
    env.update(BLENDER_USER_SCRIPTS=str(tmp_path / "user" / "scripts"),
               BLENDER_USER_CONFIG=str(tmp_path / "user" / "config"), PYTHONNOUSERSITE="1",
               PYTHONPATH=str(hide), XDG_CACHE_HOME=str(tmp_path / "cache"))
    return env


def run(command, env, timeout):
    """Runs a Blender script; returns its RESULT (asserting every check passed)."""
    result = run_group(command, timeout, env=env)
    output = result.stdout + result.stderr
    lines = [line for line in result.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, f"{command[-3:]} did not finish:\n{output[-6000:]}"
    report = json.loads(lines[-1][len("RESULT "):])
    failed = {name: text for name, text in report["checks"].items() if text != "ok"}
    assert not failed and result.returncode == 0, f"{failed}\n{output[-6000:]}"
    assert "Traceback" not in output, output[-6000:]
    return report


def script(name):
    return str(ROOT / "tests" / "blender" / name)


@pytest.mark.long
def test_artist_journey(tmp_path):
    # The zip: the add-on, its samples and the compiled module for this Python.
    made = subprocess.run(["bash", str(ROOT / "blender_addon" / "package.sh"), str(BUILD_PYTHON.parent),
                           str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert made.returncode == 0, made.stderr
    package = Path(made.stdout.strip().splitlines()[-1])
    assert package.parent == tmp_path and package.name.startswith("ifsforge_addon-") and package.suffix == ".zip"
    names = zipfile.ZipFile(package).namelist()
    abi = sys.implementation.cache_tag  # Blender's Python is this one (Debian's)
    for module in ("_core", "_vdb"):
        assert any(n.startswith(f"ifsforge_addon/vendor/ifsforge/{module}.{abi}") and n.endswith(".so")
                   for n in names), (module, abi)
    assert "ifsforge_addon/__init__.py" in names and "ifsforge_addon/presets/systems/barnsley_fern.json" in names
    assert not any("__pycache__" in n for n in names)

    env = blender_env(tmp_path)
    for folder in ("scripts", "config"):
        (tmp_path / "user" / folder).mkdir(parents=True)
    # Edit > Preferences > Add-ons > Install, into empty user folders.
    report = run([BLENDER, "-b", "--python", script("journey_install.py"), "--", "--zip", str(package),
                  "--out", str(tmp_path)], env, 120)
    if SYSTEM_MODULE.is_dir():  # the set-up installed one system-wide: it was there, and hidden
        assert not report["values"]["module"].startswith(str(SYSTEM_MODULE))
    assert len(report["values"]["compiled"]) == 2

    # A fresh scene with a window: the menus, every generator, save, undo, redo, a preset.
    # 960x600: a redraw (software OpenGL) costs 40% less CPU than at 1280x800, a save's
    # thumbnail 60% less; the menus, the sidebar and the 3D view are all still drawn.
    out = tmp_path / "journey"
    out.mkdir()
    report = run([*xvfb_run(WINDOW), BLENDER, "--enable-event-simulate",
                  "--python", script("journey_scene.py"), "--", "--out", str(out)], env, 420)
    values = report["values"]
    assert values["menus_drawn"] == ["VIEW3D_MT_add", "IFSFORGE_MT_add", "TOPBAR_MT_file_import"]
    assert values["add_Volume"][0] == "VOLUME" and values["add_Image"][0] == "EMPTY"

    # The preset in another fresh Blender makes the same object (same file digest, same result).
    run([*xvfb_run(WINDOW), BLENDER, "--python", script("journey_preset.py"), "--",
         "--preset", values["preset"], "--expect", json.dumps(values["preset_object"])], env, 180)

    # The .blend in a Blender without the add-on (factory settings, ifsforge hidden): every file
    # it names is there, and it renders.
    blend = out / "project" / "scene.blend"
    probe = tmp_path / "probe.py"
    probe.write_text(PROBE)
    factory = dict(env, BLENDER_USER_SCRIPTS=str(tmp_path / "bare" / "scripts"),
                   BLENDER_USER_CONFIG=str(tmp_path / "bare" / "config"))
    result = run_group([BLENDER, "-b", "--factory-startup", str(blend), "--python", str(probe), "--",
                        str(tmp_path / "bare.png")], 300, env=factory)
    output = result.stdout + result.stderr
    seen = json.loads(next(line for line in result.stdout.splitlines() if line.startswith("PROBE "))[6:])
    assert not seen["addon"] and not seen["imports"], seen
    assert seen["missing"] == [] and seen["volumes"] >= 2 and seen["images"] >= 3, seen
    assert "not found" not in output.lower() and "unable to open" not in output.lower(), output[-3000:]
    alpha = np.asarray(seen["alpha"])
    assert alpha > 0.02, seen


PROBE = """
import bpy, json, os, sys
import numpy as np
out = {"addon": "ifsforge_addon" in bpy.context.preferences.addons,
       "imports": [name for name in sys.modules if name.split('.')[0] in ('ifsforge', 'ifsforge_addon')]}
paths = [v.filepath for v in bpy.data.volumes] + [i.filepath for i in bpy.data.images if i.source == 'FILE']
out["missing"] = [p for p in paths if p and not os.path.isfile(bpy.path.abspath(p))]
out["volumes"] = len(bpy.data.volumes)
out["images"] = len([i for i in bpy.data.images if i.source == 'FILE'])
for volume in bpy.data.volumes:
    assert volume.grids.load(), volume.grids.error_message
scene = bpy.context.scene
scene.render.engine = 'CYCLES'
scene.cycles.samples, scene.cycles.use_denoising = 4, False
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 96, 54, 100
scene.render.film_transparent = True
scene.render.filepath = sys.argv[-1]
bpy.ops.render.render(write_still=True)
image = bpy.data.images.load(sys.argv[-1])
out["alpha"] = float(np.array(image.pixels[:]).reshape(-1, 4)[:, 3].mean())
print("PROBE " + json.dumps(out))
"""
