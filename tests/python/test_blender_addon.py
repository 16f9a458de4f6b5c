"""The Blender add-on. Its bpy-free codec is tested here directly; everything else runs in
real Blender (blender -b --factory-startup), several checks per Blender start, by the scripts
in tests/blender/ (each prints CHECK lines and a RESULT line, see addon_harness.py)."""
import importlib.util
import json
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

import ifsforge
from conftest import BUILD_PYTHON, ROOT, patience, run_group, xvfb_run

BLENDER = shutil.which("blender")


def load_codec():
    """The add-on's codec module without its package (whose __init__ imports bpy)."""
    spec = importlib.util.spec_from_file_location("ifsforge_addon_codec",
                                                  ROOT / "blender_addon" / "ifsforge_addon" / "codec.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def run_blender(script, tmp_path, timeout=120, window=False):
    """Runs tests/blender/<script> in Blender (background, or with a window under xvfb-run);
    returns the parsed RESULT (asserts every check passed)."""
    command = [BLENDER, "-b", "--factory-startup"]
    if window:
        # 960x600: each software-OpenGL redraw costs 40% less CPU than at 1024x800.
        command = [*xvfb_run("960x600"), BLENDER, "--factory-startup",
                   "--enable-event-simulate"]
    result = run_group(
        command + ["--python", str(ROOT / "tests" / "blender" / script), "--",
                   "--python-path", str(BUILD_PYTHON), "--out", str(tmp_path)], timeout,
        env=dict(os.environ, XDG_CACHE_HOME=str(tmp_path / "cache"), BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"),
                 BLENDER_USER_CONFIG=str(tmp_path / "config")))
    if window:  # panels and the draw handler run inside Blender's loop: a bug there only prints
        assert "Traceback" not in result.stdout + result.stderr, (result.stdout + result.stderr)[-4000:]
    lines = [line for line in result.stdout.splitlines() if line.startswith("RESULT ")]
    assert lines, f"{script} did not finish:\n{result.stdout[-4000:]}\n{result.stderr[-4000:]}"
    report = json.loads(lines[-1][len("RESULT "):])
    failed = {name: text for name, text in report["checks"].items() if text != "ok"}
    assert not failed and result.returncode == 0, f"{script}: {failed}\n{result.stdout[-6000:]}"
    return report


def test_codec_round_trip(samples):
    codec = load_codec()
    for path in sorted(samples.glob("*.json")):
        system = ifsforge.read_json(str(path))
        back = codec.build_system(codec.system_record(system))
        assert back.layout == system.layout and back.name == system.name
        for a, b in zip(back.maps, system.maps):
            np.testing.assert_allclose(a.matrix, b.matrix, atol=1e-12)
            np.testing.assert_allclose(a.offset, b.offset, atol=1e-12)
        np.testing.assert_allclose(back.probabilities, system.probabilities, rtol=1e-12)
    # Extra channels and their coupling into the position survive too (xyz+rgb, 6 x 6).
    rng = np.random.default_rng(4)
    maps = [ifsforge.AffineMap(rng.uniform(-0.3, 0.3, (6, 6)), rng.uniform(-1, 1, 6)) for _ in range(3)]
    system = ifsforge.Ifs(maps, [0.2, 0.3, 0.5], "xyz+rgb", "coloured")
    record = codec.system_record(system)
    assert len(record["maps"][0]["channels"]) == 3 and len(record["maps"][0]["coupling"]) == 3
    back = codec.build_system(json.loads(json.dumps(record)))  # plain JSON values suffice
    for a, b in zip(back.maps, system.maps):
        np.testing.assert_allclose(a.matrix, b.matrix, atol=1e-12)


def test_codec_defaults_and_errors(samples):
    codec = load_codec()
    record = {"name": "t", "layout": "xy+rgb+k", "probabilities": "uniform",
              "maps": [codec.default_map(i, 3, "xy+rgb+k") for i in range(3)]}
    system = codec.build_system(record)
    assert system.classify() == "hyperbolic" and system.dim == 6
    np.testing.assert_allclose(system.probabilities, [1 / 3] * 3)
    # k' = index: the primitive index of every point of piece i is i.
    np.testing.assert_allclose([m.offset[5] for m in system.maps], [0, 1, 2])
    assert all(m.matrix[5].max() == 0 for m in system.maps)
    with pytest.raises(ifsforge.InputError, match="channel rows"):
        codec.build_system(dict(record, layout="xy+gray"))
    with pytest.raises(ifsforge.InputError, match="no maps"):
        codec.build_system(dict(record, maps=[]))
    with pytest.raises(ifsforge.InputError, match="probability mode"):
        codec.build_system(dict(record, probabilities="random"))
    assert codec.extensions(json.dumps({"name": "x", "maps": [], "transitions": [[1]]})) == ["transitions"]
    polar = ifsforge.read_json(str(samples / "polar_spirals.json"))  # the import warns, not the shadows silently
    assert codec.extensions(ifsforge.to_json(polar)) == ["polar maps"]


def test_design_in_blender(tmp_path):
    report = run_blender("addon_design.py", tmp_path)
    assert report["values"]["preview_update_ms_median"] < patience(1.0) * 1000  # measured by the benchmark, not here


def test_collage_target_in_blender(tmp_path):
    report = run_blender("addon_collage.py", tmp_path)
    assert report["values"]["collage_update_ms_median"] < patience(0.05) * 1000


@pytest.mark.long
def test_install_script(tmp_path):
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(tmp_path / "scripts"), BLENDER_USER_CONFIG=str(tmp_path / "config"))
    env.pop("PYTHONPATH", None)
    build = BUILD_PYTHON.parent
    result = run_group(["bash", str(ROOT / "blender_addon" / "install.sh"), str(build)], 120, env=env)
    assert result.returncode == 0, result.stderr
    assert "enabled" in result.stdout
    addon = tmp_path / "scripts" / "addons" / "ifsforge_addon"
    assert (addon / "__init__.py").is_file() and (addon / "presets" / "systems" / "barnsley_fern.json").is_file()
    assert (addon / "presets" / "terrain" / "earth.json").is_file()
    assert (tmp_path / "config" / "userpref.blend").is_file()
    # A fresh Blender with those preferences has the add-on enabled, using the bundled module
    # (first on sys.path, whatever else is installed).
    probe = ("import addon_utils, bpy, ifsforge\n"
             "print('ENABLED', addon_utils.check('ifsforge_addon'), hasattr(bpy.types, 'IFSFORGE_PT_design'))\n"
             "print('MODULE', ifsforge.__file__)\n")
    out = run_group([BLENDER, "-b", "--python-expr", probe], 60, env=env)
    assert "ENABLED (True, True) True" in out.stdout, out.stdout + out.stderr
    assert f"MODULE {addon / 'vendor' / 'ifsforge' / '__init__.py'}" in out.stdout, out.stdout


def test_generators_in_blender(tmp_path):
    report = run_blender("addon_generate.py", tmp_path)
    values = report["values"]
    # One seed, one terrain: the add-on, the CLI and Python build the controls with the core's one
    # builder (make_terrain_controls) and give the same height field, byte for byte.
    cli_png, python_png = tmp_path / "cli_terrain.png", tmp_path / "python_terrain.png"
    subprocess.run([sys.executable, "-m", "ifsforge", "terrain", "--grid", "irregular", "--controls", "9", "9",
                    "--shift", "0.3", "--roughness", "0.375", "0.25", "--seed", "7", "--res", "65", "--extent", "4", "4",
                    "-o", str(cli_png)], check=True, env=dict(os.environ, PYTHONPATH=str(BUILD_PYTHON)))
    controls = ifsforge.make_terrain_controls(7, grid="irregular", rows=9, columns=9, shift=0.3, roughness=(0.375, 0.25))
    ifsforge.write_png(str(python_png), ifsforge.make_terrain(controls, 65, 65).height_image(65, 65), 16)
    blender_png = values["terrain_same_seed_png"]
    with open(blender_png, "rb") as f:
        assert f.read() == cli_png.read_bytes() == python_png.read_bytes()
    # An independent reader (OpenVDB's own Python module) agrees with what Blender was shown.
    pyopenvdb = pytest.importorskip("pyopenvdb")
    path, voxels = values["tetrahedron_vdb_after"]
    assert pyopenvdb.read(path, "density").activeVoxelCount() == voxels
    assert sorted(g.name for g in pyopenvdb.readAllGridMetadata(values["pyramid_vdb"])) == ["color", "density"]
    assert values["volume_render_covered"] > 0.02 and values["instances_render_covered"] > 0.03


def test_datablocks_and_files_in_blender(tmp_path):
    run_blender("addon_files.py", tmp_path)


def test_animation_and_bake_in_blender(tmp_path):
    run_blender("addon_animation.py", tmp_path, timeout=300)


@pytest.mark.long
def test_povray_scene_export_matches_blender(tmp_path):
    report = run_blender("addon_povray.py", tmp_path, timeout=300)
    assert report["values"]["silhouette_iou"] >= 0.85


def test_baked_instances_play_without_the_addon(tmp_path):
    run_blender("addon_bake_instances.py", tmp_path, timeout=300)


def test_blender_conventions(tmp_path):
    run_blender("addon_conventions.py", tmp_path)


@pytest.mark.long
def test_viewport_and_panels_with_a_window(tmp_path):
    # Drawing needs a GPU context: Blender gets a window on a virtual X display (Mesa's
    # software OpenGL). Any exception in a panel's or the draw handler's code prints a traceback.
    report = run_blender("addon_gui.py", tmp_path, timeout=300, window=True)  # software OpenGL: slow redraws
    assert report["values"]["highlighted_pixels"] > 10000  # the leaf's points, not only its frame


def test_fractal_texture_in_blender(tmp_path):
    report = run_blender("addon_fractal_texture.py", tmp_path)
    assert report["values"]["generated_psnr"] > 25


@pytest.mark.long
def test_volume_look_in_blender(tmp_path):
    report = run_blender("addon_volume_look.py", tmp_path, timeout=300)
    opacity = report["values"]["pyramid_opacity_by_resolution"]
    assert max(opacity.values()) - min(opacity.values()) <= 0.05 * max(opacity.values())
