"""Fractal interpolation, palettes and terrains through the binding and the CLI, and their files
read back by independent consumers: POV-Ray renders the scene, Blender imports the glTF."""
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ifsforge

ROOT = Path(__file__).resolve().parents[2]
SAMPLES = ROOT / "samples" / "terrain"


def controls(grid="regular", rows=5, columns=5, roughness=0.4, seed=1):
    c = ifsforge.TerrainControls()
    c.grid = grid
    if grid == "circular":
        c.radii = [k / (rows - 1) for k in range(rows)]
    c.heights = ifsforge.random_heights(grid, rows, columns, [0.5], 0.5, seed)
    maps_u = columns if grid == "circular" else columns - 1
    c.a22_u = ifsforge.vertical_scaling(maps_u, roughness, "random", seed, 1)
    c.a22_v = ifsforge.vertical_scaling(rows - 1, roughness, "random", seed, 2)
    return c


def two_tone():
    return ifsforge.make_palette(ifsforge.PaletteSpec("rgb", [[0.9, 0.1, 0.1], [0.1, 0.8, 0.2], [0.1, 0.2, 0.9]]), 256)


# --- the binding -------------------------------------------------------------------------------

def test_fractal_interpolation_binding():
    f = ifsforge.FractalInterpolation([0, 1, 2, 3], [0.0, 1.0, -0.5, 0.25], [0.6, -0.5, 0.7])
    assert [f.evaluate(x) for x in f.x] == f.values
    s = f.sample(3 * 64 + 1)
    assert s.shape == (193,) and np.allclose(s[::64], f.values, atol=1e-12)
    system = f.to_ifs()
    assert system.layout == "xy" and len(system.maps) == 3
    assert f.dimension() == pytest.approx(1 + np.log(1.8) / np.log(3))
    zero = ifsforge.FractalInterpolation([0, 1, 2, 3], [0.0, 1.0, -0.5, 0.25], [0.0])
    assert np.allclose(zero.sample(301), np.interp(np.linspace(0, 3, 301), [0, 1, 2, 3], zero.values), atol=1e-12)
    with pytest.raises(ValueError, match="increase strictly"):
        ifsforge.FractalInterpolation([0, 2, 1], [0, 1, 2], [0.1])
    with pytest.raises(ifsforge.InputError, match=r"\|a22\| < 1"):
        ifsforge.FractalInterpolation([0, 1, 2], [0, 1, 2], [1.0])
    with pytest.raises(ifsforge.InputError, match="at least 3"):
        ifsforge.FractalInterpolation([0, 1], [0, 1], [0.1])


def test_terrain_binding_hits_controls_and_ignores_threads():
    c = controls(rows=5, columns=9, roughness=0.45)
    one = ifsforge.make_terrain(c, 8 * 50 + 1, 4 * 60 + 1, threads=1)
    two = ifsforge.make_terrain(c, 8 * 50 + 1, 4 * 60 + 1, threads=2)
    assert one.heights.shape == (241, 401)
    assert np.array_equal(one.heights, two.heights)
    assert np.array_equal(one.heights[::60, ::50], np.array(c.heights, dtype=np.float32))
    image = one.height_image()
    assert image.shape == (241, 401) and image.min() == 0.0 and image.max() == 1.0
    assert np.allclose(image[::-1], (one.heights - one.min_height) / (one.max_height - one.min_height), atol=1e-6)
    positions = one.positions()
    assert positions.shape == (241, 401, 3)
    assert np.allclose(positions[0, 0, :2], [-0.5, -0.5]) and np.allclose(positions[-1, -1, :2], [0.5, 0.5])
    mesh = one.mesh(palette=two_tone())
    assert mesh["positions"].shape == (241 * 401, 3) and mesh["triangles"].shape == (2 * 240 * 400, 3)
    assert mesh["colors"].shape == (241 * 401, 4)
    assert np.allclose(mesh["positions"][:, 2], one.heights.ravel())  # ifsforge's axes: z up
    turned = one.mesh(up="y")  # (x, height, -y)
    assert np.allclose(turned["positions"], mesh["positions"][:, [0, 2, 1]] * [1, 1, -1])
    assert np.allclose(turned["normals"], mesh["normals"][:, [0, 2, 1]] * [1, 1, -1])
    cancelled = []
    with pytest.raises(ifsforge.Cancelled):
        ifsforge.make_terrain(controls(rows=9, columns=9), 4096, 64, progress=lambda f: cancelled.append(f) or False)


def test_palette_binding():
    spec = ifsforge.PaletteSpec("hls", [[20, 0.2, 0.8], [40, 0.5, 0.8], [60, 0.8, 0.8]], [], [[0], [0.5], [0]])
    p = ifsforge.make_palette(spec, 2 * 50 + 1)
    assert p.colors.shape == (101, 3) and len(p) == 101
    for k, (h, l, s) in zip((0, 50, 100), spec.stops):
        assert np.allclose(p.colors[k], ifsforge.hls_to_rgb(h, l, s), atol=1e-6)
    strip = p.to_image(4)
    assert strip.shape == (4, 101, 3)
    ramp = np.linspace(0, 1, 101, dtype=np.float32)[None, :]
    assert np.allclose(ifsforge.apply_palette(ramp, p)[0], p.colors, atol=1e-5)
    assert p.color_map().count("[") == 101
    with pytest.raises(ifsforge.InputError, match="at least 3"):
        ifsforge.make_palette(ifsforge.PaletteSpec("rgb", [[0, 0, 0], [1, 1, 1]]), 16)


def test_every_sample_recipe_loads_and_hits_its_controls():
    recipes = sorted(SAMPLES.glob("*.json"))
    terrains = [r for r in recipes if json.loads(r.read_text())["format"] == "ifsforge-terrain/1"]
    palettes = [r for r in recipes if json.loads(r.read_text())["format"] == "ifsforge-palette/1"]
    assert len(terrains) >= 4 and len(palettes) >= 3
    grids = set()
    for path in terrains:
        recipe = ifsforge.read_terrain_recipe(str(path))
        c = recipe.controls
        grids.add(c.grid)
        rows, columns = len(c.heights), len(c.heights[0])
        across = columns * 8 if c.grid == "circular" else (columns - 1) * 8 + 1
        t = ifsforge.make_terrain(c, across, (rows - 1) * 8 + 1)
        assert np.array_equal(t.heights[::8, ::8], np.array(c.heights, dtype=np.float32)), path.name
    assert grids == {"regular", "irregular", "circular"}
    for path in palettes:
        recipe = ifsforge.read_palette_recipe(str(path))
        assert len(recipe.make()) == recipe.entries


# --- the command line --------------------------------------------------------------------------

def test_cli_terrain_writes_every_output(cli, tmp_path):
    r = cli("terrain", SAMPLES / "ridge_range.json", "--res", "129x97", "-o", "ridge.png", "-o", "ridge.glb",
            "-o", "ridge.obj", "-o", "ridge.ply", "-o", "ridge.pov", "--preview", "preview.png", check=True)
    assert "ridge range" in r.stdout
    height = ifsforge.read_png(str(tmp_path / "ridge.png"))
    assert height.shape == (97, 129) and height.min() == 0.0 and height.max() == 1.0
    with open(tmp_path / "ridge.png", "rb") as f:
        assert f.read(26)[24] == 16  # IHDR bit depth
    assert ifsforge.read_png(str(tmp_path / "preview.png")).shape == (97, 129, 3)
    assert (tmp_path / "ridge_height.png").exists()
    scene = (tmp_path / "ridge.pov").read_text()
    assert 'height_field { png "ridge_height.png"' in scene and "color_map" in scene
    assert (tmp_path / "ridge.obj").read_text().count("\nv ") == 129 * 97
    assert (tmp_path / "ridge.glb").read_bytes()[:4] == b"glTF"


def test_cli_terrain_without_recipe(cli, tmp_path):
    for grid in ("regular", "irregular", "circular"):
        extra = ["--shift", "0.3"] if grid != "regular" else []
        cli("terrain", "--grid", grid, "--roughness", "0.4", "0.3", "--res", "65", "--seed", "3",
            "-o", f"{grid}.png", *extra, check=True)
        assert ifsforge.read_png(str(tmp_path / f"{grid}.png")).shape == (65, 65)
    base = tmp_path / "regular.png"
    cli("terrain", "--grid", "irregular", "--heights-from", base, "--window", "0.25", "0.25", "0.75", "0.75",
        "--controls", "5", "5", "--res", "33", "-o", "insert.png", check=True)


def test_cli_terrain_refuses_bad_input_and_writes_nothing(cli, tmp_path):
    cases = [
        (["--grid", "regular", "--roughness", "1.2", "-o", "a.png"], "argument --roughness: expects a number in [-1, 1]"),
        (["--grid", "regular", "--roughness", "1", "-o", "a.png"], "|a22| < 1"),
        (["--grid", "regular", "--controls", "4", "4", "-o", "a.png"], "at least 5 x 5"),
        (["--grid", "regular", "-o", "a.stl"], "terrain outputs end in"),
        (["--grid", "regular", "-o", "missing/a.png"], "does not exist"),
        (["--grid", "circular", "--radii", "0", "1", "-o", "a.png"], "6 radii"),
    ]
    for arguments, words in cases:
        r = cli("terrain", *arguments)
        assert r.returncode == 2, arguments
        assert words in r.stderr, r.stderr
    bad = tmp_path / "bad.json"
    recipe = json.loads((SAMPLES / "ridge_range.json").read_text())
    recipe["heights"][2][3] = "high"
    bad.write_text(json.dumps(recipe))
    r = cli("terrain", bad, "-o", "a.png")
    assert r.returncode == 2 and "/heights/2/3" in r.stderr
    recipe = json.loads((SAMPLES / "crater.json").read_text())
    recipe["radii"][1] = 0
    del recipe["palette"]
    bad.write_text(json.dumps(recipe))
    r = cli("terrain", bad, "-o", "a.png")
    assert r.returncode == 2 and "increase" in r.stderr
    assert not (tmp_path / "a.png").exists() and not (tmp_path / "a.stl").exists()


def test_cli_palette_and_interpolate(cli, tmp_path):
    cli("palette", SAMPLES / "ember_hls.json", "--entries", "300", "--rows", "8", "--bits", "16",
        "-o", "ember.png", "-o", "ember.inc", check=True)
    strip = ifsforge.read_png(str(tmp_path / "ember.png"))
    assert strip.shape == (8, 300, 3)
    inc = (tmp_path / "ember.inc").read_text()
    assert inc.count("[") == 256 and "#declare IFS_Palette_ember_lightness = color_map {" in inc
    cli("palette", "--space", "rgb", "--stops", "0,0,0", "1,0,0", "1,1,1", "--roughness", "0", "0", "0",
        "--entries", "3", "-o", "linear.png", check=True)
    assert np.allclose(ifsforge.read_png(str(tmp_path / "linear.png"))[0], [[0, 0, 0], [1, 0, 0], [1, 1, 1]])
    gray = np.linspace(0, 1, 64, dtype=np.float32)[None, :].repeat(4, 0)
    ifsforge.write_png(str(tmp_path / "gray.png"), gray, 16)
    cli("palette", SAMPLES / "earth.json", "--apply", "gray.png", "coloured.png", check=True)
    assert ifsforge.read_png(str(tmp_path / "coloured.png")).shape == (4, 64, 3)
    r = cli("palette", "--stops", "0,0,0", "1,1,1", "-o", "two.png")
    assert r.returncode == 2 and "at least 3" in r.stderr and not (tmp_path / "two.png").exists()

    cli("interpolate", "--x", "0", "1", "2", "3", "--values", "0", "1", "0.3", "0.8", "--a22", "0.5", "-0.6", "0.4",
        "-o", "fif.json", "-o", "fif.csv", "--samples", "7", check=True)
    system = ifsforge.read_json(str(tmp_path / "fif.json"))
    assert len(system.maps) == 3 and system.layout == "xy"
    rows = (tmp_path / "fif.csv").read_text().split()
    assert rows[0] == "x,f" and len(rows) == 8 and rows[-1] == "3.0,0.8"
    r = cli("interpolate", "--x", "0", "1", "1", "--values", "0", "1", "2", "--a22", "0.2", "-o", "x.json")
    assert r.returncode == 2 and "increase strictly" in r.stderr


# --- real consumers ----------------------------------------------------------------------------

@pytest.mark.parametrize("shape", ["height_field", "mesh2"])
def test_povray_renders_the_palette_on_the_heights(tmp_path, shape):
    # Seen straight down without lights, every pixel must show the palette colour of its height:
    # the render equals apply_palette(height image) up to resampling at the pixel centres.
    c = controls(rows=5, columns=5, roughness=0.25, seed=4)
    c.size_x, c.size_y = 4.0, 3.0
    terrain = ifsforge.make_terrain(c, 129, 97)
    palette = two_tone()
    scene = tmp_path / "flat.pov"
    ifsforge.write_terrain_pov(str(scene), terrain, palette, shape=shape, camera="top", flat=True)
    ifsforge.render_povray(str(scene), str(tmp_path / "flat.png"), 128, 96)
    render = ifsforge.read_png(str(tmp_path / "flat.png"))[..., :3]
    # The terrain's colours at POV-Ray's pixel centres: pixel i of 128 sits at sample 128 i / 127 ... of 129.
    expected = ifsforge.apply_palette(terrain.height_image(), palette)
    xs = np.clip(np.round((np.arange(128) + 0.5) * 128 / 128).astype(int), 0, 128)
    ys = np.clip(np.round((np.arange(96) + 0.5) * 96 / 96).astype(int), 0, 96)
    expected = expected[ys][:, xs]
    error = np.abs(render - expected).mean()
    mirrored = np.abs(render - expected[::-1]).mean()
    assert error < 0.02, error
    assert mirrored > 3 * error  # the comparison can tell north from south


def test_blender_imports_the_glb(tmp_path):
    c = controls(grid="circular", rows=5, columns=8, roughness=0.35, seed=2)
    ifsforge.random_shifts(c, 0.3, 1)
    terrain = ifsforge.make_terrain(c, 64, 33)
    palette = ifsforge.read_palette_recipe(str(SAMPLES / "glacier_hsi.json")).make(200)
    path = tmp_path / "crater.glb"
    ifsforge.write_terrain_mesh(str(path), terrain, palette)
    mesh = terrain.mesh()
    xmin, ymin, xmax, ymax = terrain.extent
    outer = terrain.positions()[-1]  # the outer circle: its extent is the mesh's
    args = [path, len(mesh["positions"]), len(mesh["triangles"]), 200,
            outer[:, 0].max() - outer[:, 0].min(), outer[:, 1].max() - outer[:, 1].min(),
            terrain.max_height - terrain.min_height]
    script = ROOT / "tests" / "blender" / "terrain_glb_import.py"
    r = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python", str(script),
                        "--", *map(str, args)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert "OK 2049 vertices" in r.stdout


def test_the_command_line_default_terrain_is_the_cores(cli, tmp_path):
    # Each default lives once, in the core: the command's terrain without options is the one
    # make_terrain_controls and terrain_defaults describe (the add-on's panel reads the same).
    cli("terrain", "-o", "cli.png", "--seed", "3", check=True)
    defaults = ifsforge.terrain_defaults
    controls = ifsforge.make_terrain_controls(3)
    assert np.shape(controls.heights) == (defaults["controls"], defaults["controls"])
    # Rough, not the bilinear sheet through the controls that no roughness gives.
    assert controls.a22_u and all(abs(a) == pytest.approx(defaults["roughness"]) for a in controls.a22_u)
    n = defaults["samples"]
    ifsforge.write_png(str(tmp_path / "core.png"), ifsforge.make_terrain(controls, n, n).height_image(n, n), 16)
    assert (tmp_path / "cli.png").read_bytes() == (tmp_path / "core.png").read_bytes()
    assert ifsforge.read_png(str(tmp_path / "cli.png")).shape[:2] == (n, n)


def test_terrain_extent_has_its_own_name(cli, tmp_path):
    # --size is pixels in every other command; a terrain's world extent is --extent (--size stays
    # one release as a deprecated spelling).
    new = cli("terrain", "-o", "a.obj", "--res", "17", "--extent", "8", "2", check=True)
    old = cli("terrain", "-o", "b.obj", "--res", "17", "--size", "8", "2", check=True)
    assert "deprecated" in old.stderr and "deprecated" not in new.stderr
    def vertices(name):
        return [line for line in (tmp_path / name).read_text().splitlines() if line.startswith("v ")]
    assert vertices("a.obj") == vertices("b.obj")
    xs = [float(line.split()[1]) for line in vertices("a.obj")]
    assert max(xs) - min(xs) == pytest.approx(8.0)
