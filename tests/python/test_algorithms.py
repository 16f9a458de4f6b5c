"""The algorithm catalogue through Python and the CLI: parameters, recurrent and super IFS,
condensation sets, growth frames, the compare report and the samples. The algorithms
themselves are tested in tests/cpp/test_algorithms.cpp; this tests the binding and the CLI."""
import json
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import ifsforge
from conftest import SAMPLES, ifsforge_command

# The build this module was imported from: the CLI runs against the same one.
BUILD_PYTHON = Path(ifsforge.__file__).resolve().parents[1]
NEW_SAMPLES = ["superfractal_pair", "recurrent_squares", "condensation_tree", "colour5d_sierpinski_rgb",
               "colour5d_fern_hsi", "colour5d_dragon_rgb", "rgba_carpet"]


@pytest.fixture
def run_cli(tmp_path):
    def run(*args):
        env = dict(os.environ, PYTHONPATH=str(BUILD_PYTHON))
        return subprocess.run([*ifsforge_command(), *map(str, args)],
                              capture_output=True, text=True, env=env, cwd=tmp_path)
    return run


def load(name):
    return ifsforge.read_json(str(SAMPLES / f"{name}.json"))


def window(system):
    return system.render_defaults.get("window")


def test_every_chapter_five_algorithm_is_registered_with_its_parameters():
    names = [n for n, _ in ifsforge.renderers()]
    assert names == ["chaos", "color-stealing", "dia", "dia-s", "mpa", "cma", "eta", "string-rewriting", "tsa",
                     "prr", "ibr", "afra", "self-congruent", "photocopy", "probabilistic-domain", "tops"]
    eta = {key: default for key, default, _ in ifsforge.renderer_parameters("eta")}
    assert eta["norm"] == "euclidean" and eta["rule"] == "min"
    # PRR's cut is automatic: half a pixel for coverage, one pixel for the measure.
    prr = ifsforge.renderer_parameters("prr")
    assert [(key, default) for key, default, _ in prr] == [("cut", "")]
    assert "1/2 for coverage" in prr[0][2] and "1 for the measure" in prr[0][2]


def test_string_rewriting_and_tsa_have_one_name_each():
    # 5.6 and 5.7 are reached as the renderers "string-rewriting" and "tsa" and, for their
    # addresses, ifsforge.string_rewriting / ifsforge.tesseral_synecdoche: no other spelling.
    fern = load("barnsley_fern")
    for other in ("srwa", "strings", "tesseral-synecdoche"):
        with pytest.raises(ifsforge.InputError, match=other):
            ifsforge.render(fern, other, 16)
    assert not hasattr(ifsforge, "rewrite_strings")
    assert ifsforge.choices["spelling"] == ["digits", "seed"]


def test_parameters_pass_as_numbers_or_text_and_unknown_ones_are_refused():
    system = load("sierpinski_triangle")
    a = ifsforge.render(system, "tsa", 64, window=window(system), parameters={"threshold": 1e-4})
    b = ifsforge.render(system, "tsa", 64, window=window(system), parameters={"threshold": "1e-4"})
    assert np.array_equal(a.density, b.density)
    with pytest.raises(ifsforge.InputError, match="no parameter 'treshold'"):
        ifsforge.render(system, "tsa", 64, parameters={"treshold": 1})
    with pytest.raises(ValueError, match="takes none"):  # InputError is a ValueError
        ifsforge.render(system, "afra", 64, parameters={"depth": 3})


def test_recurrent_ifs_from_python():
    squares = load("recurrent_squares")
    assert squares.recurrent
    np.testing.assert_allclose(squares.stationary_distribution(), [0.25] * 4)
    assert squares.piece_points().shape == (4, 2)
    plain = ifsforge.Ifs(squares.maps, layout="xy", name="squares")
    assert not plain.recurrent and plain.transitions is None
    plain.transitions = squares.transitions
    np.testing.assert_allclose(plain.transitions.sum(axis=1), 1.0)
    with pytest.raises(ifsforge.InputError, match="reducible"):
        plain.transitions = np.eye(4)
    again = ifsforge.parse_json(ifsforge.to_json(squares))
    np.testing.assert_array_equal(again.transitions, squares.transitions)
    # Random iteration follows the transitions too.
    chaos = ifsforge.render(squares, "chaos", 128, window=window(squares), iterations=2_000_000)
    pd = ifsforge.render(squares, "probabilistic-domain", 128, window=window(squares))
    union = np.logical_or(chaos.mask, pd.mask).sum()
    assert np.logical_and(chaos.mask, pd.mask).sum() / union > 0.9


def test_super_ifs_from_python():
    pair = load("superfractal_pair")
    info = pair.super_ifs
    assert info["names"] == ["spreading tree", "upright tree"] and info["variability"] == 2
    spreading, upright = pair.member(0), pair.member(1)
    made = ifsforge.make_super_ifs("again", [spreading, upright], [1, 1], variability=3)
    assert made.super_ifs["sizes"] == [3, 3] and made.super_ifs["variability"] == 3
    w = window(pair)
    first = ifsforge.render(pair, "dia-s", 96, window=w, seed=1).density
    assert np.array_equal(first, ifsforge.render(pair, "dia-s", 96, window=w, seed=1).density)
    assert not np.array_equal(first, ifsforge.render(pair, "dia-s", 96, window=w, seed=2).density)
    with pytest.raises(ifsforge.InputError, match="layout"):
        ifsforge.make_super_ifs("mixed", [spreading, load("colour5d_fern_hsi")])


def test_condensation_sets_and_growth_frames():
    tree = load("condensation_tree")
    trunk = tree.condensation
    assert trunk.polygons and trunk.probability == pytest.approx(0.2)
    bare = ifsforge.Ifs(tree.maps, list(tree.probabilities), name="bare")
    assert bare.condensation is None and bare.condensation_box is None
    bare.condensation = ifsforge.Condensation(polylines=[[[0, 0], [0, 1.12]]], probability=0.1)
    assert bare.condensation.bounds() == pytest.approx([0, 0, 0, 1.12])
    # The attractor with C holds C and its images: a box around the trunk's, reaching above it.
    box = bare.condensation_box
    assert box[0] < 0 < box[2] and box[1] <= 0 and box[3] > 1.12
    with pytest.raises(ifsforge.InputError, match="at least 2 points"):
        bare.condensation = ifsforge.Condensation(polylines=[[[0, 0]]])
    frames = ifsforge.growth_frames(tree, 96, window=window(tree))
    assert len(frames) > 5
    masks = [f.mask for f in frames]
    for earlier, later in zip(masks, masks[1:]):
        assert not (earlier & ~later).any()  # growth never loses a pixel
    assert masks[-1].sum() > 5 * masks[0].sum()
    # The density of the last frame is each pixel's age in cycles: the trunk is the oldest.
    assert frames[-1].density.max() == len(frames)


def test_strings_bounds_and_color_bounds():
    fern = load("barnsley_fern")
    strings = ifsforge.string_rewriting(fern, 2, spelling="seed")
    assert len(strings) == 16 and strings[:2] == ["w1w1", "w2w1"]
    # The vector layer's spelling of the same rewriting: "1.0" for "w2w1", in the same order.
    assert ifsforge.string_rewriting(fern, 2) == [
        ".".join(str(int(d) - 1) for d in s.split("w")[1:]) for s in strings]
    bound = ifsforge.proximity_bound(fern, 256, window=window(fern))
    assert bound == pytest.approx(0.5 * np.sqrt(2) * (10.2983 + 0.3) / 256 / (1 - np.hypot(0.85, 0.04)), rel=1e-6)
    lo, hi = ifsforge.color_bounds(load("colour5d_sierpinski_rgb"), levels=4)
    assert lo.shape == (3,) and (lo < hi).all()


@pytest.mark.parametrize("name", NEW_SAMPLES)
def test_new_samples_render_with_their_algorithm(name, tmp_path):
    system = load(name)
    defaults = system.render_defaults
    raster = ifsforge.render(system, defaults.get("algorithm", "chaos"), 128, window=window(system))
    assert raster.covered() > 300
    if system.layout != "xy":
        image = raster.to_image("color")
        path = tmp_path / f"{name}.png"
        ifsforge.write_png(str(path), image, bit_depth=16)
        back = ifsforge.read_png(str(path))
        assert back.shape == image.shape
        np.testing.assert_allclose(back, np.clip(image, 0, 1), atol=1 / 65535 + 1e-6)
        assert back.shape[2] == (4 if system.layout == "xy+rgba" else 3)


def test_cli_render_takes_parameters(run_cli, tmp_path):
    result = run_cli("render", SAMPLES / "sierpinski_triangle.json", "-o", "eta.png", "--size", "64",
                     "-a", "eta", "--param", "norm=linear", "--param", "output=escape-time")
    assert result.returncode == 0, result.stderr
    assert (tmp_path / "eta.png").exists()
    bad = run_cli("render", SAMPLES / "sierpinski_triangle.json", "-o", "bad.png", "--size", "64", "-a", "eta",
                  "--param", "norm=manhattan")
    assert bad.returncode == 2 and "norm" in bad.stderr
    assert not (tmp_path / "bad.png").exists()
    listing = run_cli("algorithms")
    assert "--param supersample=2" in listing.stdout and "escape time" in listing.stdout


def test_cli_compare_writes_the_report(run_cli, tmp_path):
    result = run_cli("compare", SAMPLES / "sierpinski_triangle.json", "-o", "report", "--size", "96",
                     "--algorithms", "mpa,eta,prr,afra,dia", "--param", "dia.iterations=200")
    assert result.returncode == 0, result.stderr
    report = tmp_path / "report"
    for name in ["contact_sheet.png", "comparison.md", "comparison.json", "mpa.png", "eta.png", "afra.png"]:
        assert (report / name).exists(), name
    data = json.loads((report / "comparison.json").read_text())
    rows = {row["algorithm"]: row for row in data["rows"]}
    assert list(rows) == ["dia", "mpa", "eta", "prr", "afra"]  # chapter-5 order
    assert rows["prr"]["iou"] == pytest.approx(1.0)
    # mpa maps each covered cell of its (default 2x supersampled) grid once by each of the 3 maps.
    assert rows["eta"]["iou"] > 0.85 and rows["mpa"]["operations"] % 3 == 0
    assert rows["mpa"]["operations"] >= 3 * rows["mpa"]["covered"]
    assert rows["dia"]["note"] == "iterations=200" and "iou_supersample_1" in rows["dia"]
    assert "| eta | 5.5 |" in (report / "comparison.md").read_text()
    sheet = ifsforge.read_png(str(report / "contact_sheet.png"))
    assert sheet.shape[2] == 3 and sheet.shape[1] == 5 * 256
    # A fern is no tile system: afra's row says why instead of failing the report.
    fern = run_cli("compare", SAMPLES / "barnsley_fern.json", "-o", "fern", "--size", "64", "--algorithms", "afra,mpa")
    assert fern.returncode == 0, fern.stderr
    rows = {row["algorithm"]: row for row in json.loads((tmp_path / "fern" / "comparison.json").read_text())["rows"]}
    assert rows["afra"]["iou"] is None and "rotates or shears" in rows["afra"]["note"]
    assert rows["mpa"]["iou"] > 0.8
    missing = run_cli("compare", SAMPLES / "barnsley_fern.json", "-o", "no/such/folder", "--size", "32")
    assert missing.returncode == 2 and not (tmp_path / "no").exists()


def test_cli_growth_writes_frames(run_cli, tmp_path):
    result = run_cli("growth", SAMPLES / "condensation_tree.json", "-o", "frames", "--size", "64", "--cycle", "2")
    assert result.returncode == 0, result.stderr
    frames = sorted((tmp_path / "frames").glob("frame_*.png"))
    assert len(frames) > 3
    first, last = ifsforge.read_png(str(frames[0])), ifsforge.read_png(str(frames[-1]))
    assert (last > 0).sum() > (first > 0).sum()


def test_seed_reference_lives_on_the_registry():
    # 5.13.1's random-iteration estimate is Eq. 44 at one point per pixel (H V 8).
    assert ifsforge.seed_reference("chaos") == ("5.1.1", ifsforge.default_iterations(1000, 1000, points_per_pixel=1))
    assert ifsforge.seed_reference("ria") == ifsforge.seed_reference("chaos")  # an alias, the same renderer
    assert ifsforge.seed_reference("photocopy") == ("5.12.1", None)  # the seed gives no estimate
    with pytest.raises(ifsforge.InputError, match="unknown algorithm"):
        ifsforge.seed_reference("no-such")
