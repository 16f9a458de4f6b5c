"""The inverse problem from Python and the CLI: collage distance (Eq. 41-42) and fitting."""
import json
import os

import numpy as np
import pytest

import ifsforge

from conftest import SAMPLES

SQUARE = """{"format": "ifsforge/1", "name": "square", "layout": "xy", "maps": [
 {"scale": 0.5, "translation": [0, 0]}, {"scale": 0.5, "translation": [0.5, 0]},
 {"scale": 0.5, "translation": [0, 0.5]}, {"scale": 0.5, "translation": [0.5, 0.5]}],
 "render": {"window": [0, 0, 1, 1]}}"""


def test_collage_cli_of_an_exact_tiling(cli, tmp_path):
    # A white square on black, laid on [0, 1]^2: its four half copies tile it exactly.
    picture = np.zeros((40, 40), np.float32)
    picture[8:32, 8:32] = 1
    ifsforge.write_png(str(tmp_path / "t.png"), picture)
    (tmp_path / "square.json").write_text(SQUARE)
    report = json.loads(cli("collage", "square.json", "t.png", "--json", check=True).stdout)
    # Target pixels 8..31 on both axes; the copies cover [4, 16) and [24, 36) on both axes. The
    # farthest target pixels from the collage are (19, 19)-like, sqrt(4^2 + 4^2) from (15, 15);
    # the farthest collage pixels from the target are the corners (4, 4) and (35, 35), as far.
    assert report["distance_pixels"] == pytest.approx(32 ** 0.5)
    collage = ifsforge.collage_mask(ifsforge.parse_json(SQUARE), picture > 0.5)
    assert collage[4:16, 4:16].all() and collage[24:36, 24:36].all() and collage.sum() == 4 * 12 * 12
    assert ifsforge.hausdorff_distance(picture > 0.5, collage) == pytest.approx(32 ** 0.5)
    assert report["contraction"] == 0.5
    assert report["bound_pixels"] == pytest.approx(2 * report["distance_pixels"])
    assert report["target_pixels"] == 24 * 24


def test_collage_cli_names_a_bad_target(cli, tmp_path):
    (tmp_path / "square.json").write_text(SQUARE)
    ifsforge.write_png(str(tmp_path / "blank.png"), np.zeros((8, 8), np.float32))
    result = cli("collage", "square.json", "blank.png")
    assert result.returncode != 0
    assert "blank.png" in result.stderr and "no shape" in result.stderr


def sierpinski_target(size):
    system = ifsforge.load(str(SAMPLES / "sierpinski_triangle.json"))
    return np.asarray(ifsforge.render(system, "chaos", size, size, binary=True).mask, bool)


def test_fit_recovers_a_sierpinski_triangle(cli, tmp_path):
    target = sierpinski_target(96)
    ifsforge.write_png(str(tmp_path / "t.png"), target.astype(np.float32))
    summary = json.loads(cli("fit", "t.png", "-o", "fit.json", "--maps", "3", "--restarts", "2", "--seed", "1",
                             "--json", check=True).stdout)
    system = ifsforge.read_json(str(tmp_path / "fit.json"))
    assert len(system) == 3 and summary["maps"] == 3
    assert max(system.contraction_factors()) < 0.9 + 1e-9
    # The last search, on the attractor's IoU at the picture's resolution, recovers it (0.98 here).
    assert ifsforge.attractor_iou(system, target) >= 0.95
    # render.window and the size frame the attractor exactly like the target.
    cli("render", "fit.json", "-o", "fit.png", "--mode", "binary", check=True)
    drawn = ifsforge.read_png(str(tmp_path / "fit.png"))
    drawn = (drawn if drawn.ndim == 2 else drawn[..., :3].max(axis=2)) > 0.05
    assert drawn.shape == target.shape
    assert (drawn & target).sum() / (drawn | target).sum() >= 0.95


def test_maps_auto_stops_at_the_count_that_pays(cli, tmp_path):
    # The triangle is three half copies: a fourth and a fifth map buy nothing, so auto probes
    # 2 to 5 and fits the three it chose.
    ifsforge.write_png(str(tmp_path / "t.png"), sierpinski_target(48).astype(np.float32))
    summary = json.loads(cli("fit", "t.png", "-o", "fit.json", "--maps", "auto", "--restarts", "1", "--json",
                             check=True).stdout)
    assert summary["maps"] == 3 and [p["maps"] for p in summary["probes"]] == [2, 3, 4, 5], summary
    assert len(ifsforge.read_json(str(tmp_path / "fit.json"))) == 3


def test_fit_is_identical_for_any_thread_count():
    target = sierpinski_target(40)
    # Four restarts: one of each start (k-means, turned k-means, the two covers by turned copies).
    runs = [ifsforge.fit(target, maps=2, restarts=4, generations=30, attractor_generations=5,
                         refine_generations=5, final_generations=5, seed=3, threads=t) for t in (1, 2)]
    assert ifsforge.to_json(runs[0]["system"]) == ifsforge.to_json(runs[1]["system"])
    other = ifsforge.fit(target, maps=2, restarts=1, generations=30, attractor_generations=5,
                         refine_generations=5, final_generations=5, seed=4, threads=2)
    assert ifsforge.to_json(other["system"]) != ifsforge.to_json(runs[0]["system"])


def test_a_started_fit_keeps_its_start_without_the_last_search():
    # --maps auto hands its best probe to the final fit: the restarts and the refinement are
    # skipped, so without the last search the start comes back as it was, scored by its IoU (at
    # 64 pixels the last search's grid is the picture's).
    target = sierpinski_target(64)
    start = ifsforge.parse_json(json.dumps({"format": "ifsforge/1", "name": "start", "layout": "xy", "maps": [
        {"scale": 0.5, "translation": [0, 0]}, {"scale": 0.5, "translation": [0.5, 0]},
        {"scale": 0.5, "translation": [0.25, 0.5]}]}))
    result = ifsforge.fit(target, maps=3, start=start, final_generations=0)
    assert json.loads(ifsforge.to_json(result["system"]))["maps"] == json.loads(ifsforge.to_json(start))["maps"]
    assert result["restarts"] == 0 and result["iou"] == pytest.approx(ifsforge.attractor_iou(start, target))
    with pytest.raises(ifsforge.InputError, match="start"):
        ifsforge.fit(target, maps=2, start=start)


def test_fit_refuses_bad_options(cli, tmp_path):
    ifsforge.write_png(str(tmp_path / "t.png"), sierpinski_target(32).astype(np.float32))
    result = cli("fit", "t.png", "-o", "x.json", "--maps", "many")
    assert result.returncode != 0 and "--maps" in result.stderr
    result = cli("fit", "t.png", "-o", "x.json", "--max-contraction", "1.5")
    assert result.returncode != 0 and "contraction" in result.stderr
    assert not (tmp_path / "x.json").exists()


def test_address_of_cantor_dust_points(cli, samples):
    # A point of the dust w_a0(w_a1(...(corner))) has exactly that address: the pieces are apart.
    dust = ifsforge.load(str(samples / "cantor_dust.json"))
    rng = np.random.default_rng(5)
    for _ in range(20):
        address = [int(a) for a in rng.integers(0, 4, 6)]
        x = y = 0.0  # the fixed point of map 0
        for a in reversed(address):
            x, y = x / 3 + (2 / 3) * (a % 2), y / 3 + (2 / 3) * (a // 2)
        found, distance = dust.address_of([x, y], 6)
        assert found == [address] and distance == pytest.approx(0, abs=1e-12)
    result = json.loads(cli("address", str(samples / "cantor_dust.json"), "0.99", "0.01", "--depth", "3", "--json",
                            check=True).stdout)
    assert result["addresses"] == [[1, 1, 1]]  # the bottom-right piece of side 1/27
    result = cli("address", str(samples / "cantor_dust.json"), "0.5", "--depth", "3")
    assert result.returncode != 0 and "coordinates" in result.stderr


def test_tops_address_of_a_pixel_is_its_analytic_address():
    # The filled square of four half maps: pixel (x, y) of a 64^2 image of [0, 1]^2 lies in the
    # depth-6 piece whose digit k is bit k of x plus twice bit k of y (top-left origin flipped).
    square = ifsforge.parse_json(SQUARE)
    digits, covered = ifsforge.tops(square, 64, 64, seed=2)
    assert covered.all()
    for row, col in [(0, 0), (63, 63), (10, 40), (33, 7), (50, 21)]:
        x, y = col, 63 - row
        expected = [((x >> (5 - k)) & 1) + 2 * ((y >> (5 - k)) & 1) for k in range(6)]
        assert list(digits[row, col, :6]) == expected


def test_warp_from_f_to_f_gives_the_picture_back(cli, tmp_path):
    (tmp_path / "square.json").write_text(SQUARE)
    yy, xx = np.mgrid[0:128, 0:128] / 127.0
    picture = np.stack([xx, yy, 0.5 + 0.5 * np.sin(6 * xx) * np.cos(4 * yy)], axis=2).astype(np.float32)
    ifsforge.write_png(str(tmp_path / "p.png"), picture)
    cli("warp", "p.png", "--from", "square.json", "--to", "square.json", "-o", "w.png", "--size", "128", check=True)
    warped = ifsforge.read_png(str(tmp_path / "w.png"))
    assert warped.shape == (128, 128, 4) and (warped[..., 3] == 1).all()
    mse = float(((warped[..., :3] - ifsforge.read_png(str(tmp_path / "p.png"))) ** 2).mean())
    assert 10 * np.log10(1 / mse) > 30
    cli("warp", "p.png", "--from", "square.json", "--to", "square.json", "-o", "frames", "--size", "32",
        "--frames", "3", check=True)
    assert sorted(os.listdir(tmp_path / "frames")) == [f"frame_{k:04d}.png" for k in range(3)]
    result = cli("warp", "p.png", "--from", "square.json", "--to", str(SAMPLES / "sierpinski_triangle.json"),
                 "-o", "x.png")
    assert result.returncode != 0 and "same number of maps" in result.stderr and not (tmp_path / "x.png").exists()


def test_render_tops_colors_by_top_address(cli, tmp_path):
    # With the square's own maps as the reference system, each pixel's top address leads back
    # to itself and the picture comes back.
    (tmp_path / "square.json").write_text(SQUARE)
    yy, xx = np.mgrid[0:64, 0:64] / 63.0
    picture = np.stack([xx, yy, 1 - xx * yy], axis=2).astype(np.float32)
    ifsforge.write_png(str(tmp_path / "p.png"), picture)
    cli("render", "square.json", "-o", "t.png", "-a", "tops", "--reference", "p.png", "--reference-system",
        "square.json", "--size", "64", check=True)
    drawn = ifsforge.read_png(str(tmp_path / "t.png"))[..., :3]
    mse = float(((drawn - ifsforge.read_png(str(tmp_path / "p.png"))) ** 2).mean())
    assert 10 * np.log10(1 / mse) > 30
    result = cli("render", "square.json", "-o", "u.png", "-a", "tops")
    assert result.returncode != 0 and "reference" in result.stderr


def covered_by_chaos(system, size, points):
    """Pixels the system's own chaos game covers with `points` points on its render.window."""
    raster = ifsforge.render(system, "chaos", size, size, iterations=points, binary=True,
                             window=system.render_defaults["window"])
    return int(np.asarray(raster.mask, bool).sum())


def test_tops_and_warp_walk_the_system_with_its_own_probabilities():
    # The fern's maps have probabilities 0.01, 0.85, 0.07, 0.07; drawn with the square's uniform
    # ones, its top half would stay nearly blank. Both cover what its own chaos game covers.
    fern = ifsforge.load(str(SAMPLES / "barnsley_fern.json"))
    points = 16 * 128 * 128
    own = covered_by_chaos(fern, 128, points)
    _, covered = ifsforge.tops(fern, 128, 128, iterations=points, seed=1)
    yy, xx = np.mgrid[0:32, 0:32] / 31.0
    picture = np.stack([xx, yy, 0.5 + 0 * xx], axis=2).astype(np.float32)
    warped = ifsforge.tops_warp(ifsforge.parse_json(SQUARE), picture, fern, 128, 128, iterations=points, seed=1)
    for count in (int(covered.sum()), int((warped[..., 3] > 0).sum())):
        assert abs(count - own) <= TOPS_COVERAGE_BAR * own, (count, own)


# Relative difference of two chaos games' coverage at the same count (their streams differ) plus
# the pinholes tops fill from their neighbours.
TOPS_COVERAGE_BAR = 0.03


def test_warp_covers_the_whole_support(cli, tmp_path):
    # A filled square whose measure is uneven (probabilities 0.85, 0.05, 0.05, 0.05): sixteen
    # points per pixel leave pinholes in the thin corners; the walk goes on until it finds them.
    skewed = json.loads(SQUARE)  # the square's maps, its window
    for m, p in zip(skewed["maps"], (0.85, 0.05, 0.05, 0.05)):
        m["probability"] = p
    (tmp_path / "skewed.json").write_text(json.dumps(skewed))
    (tmp_path / "square.json").write_text(SQUARE)
    ifsforge.write_png(str(tmp_path / "p.png"), np.full((16, 16, 3), 0.5, np.float32))
    cli("warp", "p.png", "--from", "square.json", "--to", "skewed.json", "-o", "w.png", "--size", "128", check=True)
    assert (ifsforge.read_png(str(tmp_path / "w.png"))[..., 3] == 1).all()
    # --iterations fixes the count: too few points leave most of it transparent.
    result = cli("warp", "p.png", "--from", "square.json", "--to", "skewed.json", "-o", "few.png", "--size", "128",
                 "--iterations", "1000", check=True)
    few = int((ifsforge.read_png(str(tmp_path / "few.png"))[..., 3] > 0).sum())
    assert few <= 1000 and f"{few} pixels" in result.stdout


def test_collage_window_lays_the_target_where_it_was_drawn(cli, tmp_path):
    # The triangle drawn with a margin: on its attractor's frame the target is misplaced, on the
    # window it was drawn on its own maps give a collage within a pixel's diagonal.
    triangle = json.loads((SAMPLES / "sierpinski_triangle.json").read_text())
    del triangle["render"]
    (tmp_path / "tri.json").write_text(json.dumps(triangle))
    window = ["-0.25", "-0.25", "1.25", "1.25"]
    cli("render", "tri.json", "-o", "t.png", "--size", "128", "--mode", "binary", "--window", *window, check=True)
    laid = json.loads(cli("collage", "tri.json", "t.png", "--window", *window, "--json", check=True).stdout)
    framed = json.loads(cli("collage", "tri.json", "t.png", "--json", check=True).stdout)
    assert laid["window"] == [-0.25, -0.25, 1.25, 1.25]
    assert laid["distance_pixels"] <= 2 ** 0.5 + 1e-9 and framed["distance_pixels"] > 5
    same = ifsforge.collage_distance(ifsforge.read_json(str(tmp_path / "tri.json")),
                                     ifsforge.read_png(str(tmp_path / "t.png")), window=[-0.25, -0.25, 1.25, 1.25])
    assert same["distance_pixels"] == laid["distance_pixels"]
    result = cli("collage", "tri.json", "t.png", "--window", "1", "0", "0", "1")
    assert result.returncode != 0 and "window" in result.stderr


@pytest.mark.parametrize("name, maps", [("sierpinski_triangle", 3), ("heighway_dragon", 2), ("cantor_dust", 4)])
def test_fit_takes_a_default_render_touching_the_frame_as_its_shape(cli, tmp_path, name, maps):
    # `render` without a window frames the attractor tightly: it touches the frame (the triangle
    # covers half the border), and the white attractor on black is still the shape. 64 pixels:
    # the frame touches as much of the border at any size, and the fit's refinement costs about
    # its pixels (5-10 CPU seconds a case here against 14-15 at 128).
    system = json.loads((SAMPLES / f"{name}.json").read_text())
    del system["render"]
    (tmp_path / "s.json").write_text(json.dumps(system))
    cli("render", "s.json", "-o", "t.png", "--size", "64", "--mode", "binary", check=True)
    summary = json.loads(cli("fit", "t.png", "-o", "fit.json", "--maps", str(maps), "--restarts", "3", "--json",
                             check=True).stdout)
    assert summary["iou"] >= 0.9, summary
    # The fit writes the window it used: the collage reads it back and scores what the fit scored.
    collage = json.loads(cli("collage", "fit.json", "t.png", "--json", check=True).stdout)
    assert collage["distance_pixels"] == pytest.approx(summary["collage_distance_pixels"])
