"""Polar IFS (seed 3.3.3, Eq. 30-32) from Python and the command line: the same names as C++,
local contraction, files, rendering, `info` and `breed`."""
import json
import math

import numpy as np
import pytest

import ifsforge


@pytest.fixture
def spirals(samples):
    return ifsforge.read_json(str(samples / "polar_spirals.json"))


def test_polar_map_is_locally_contractive_eq30():
    rng = np.random.default_rng(30)
    m = ifsforge.PolarMap((0.2, -0.1), 1.5, F=[-0.1, 0.4, 0.3, -0.2, 0.1, 0.2], G=[0.7, 1.1, 0.3, -0.2], winding=-1)
    s = m.contraction()
    assert 0 < s < 1
    assert s == pytest.approx((math.tanh(m.k * m.f_bound()) + 1) / 2, rel=1e-15)
    for x, y in rng.uniform(-3, 3, size=(10_000, 2)):
        X, Y = m((x, y))
        assert math.hypot(X - 0.2, Y + 0.1) < s * math.hypot(x - 0.2, y + 0.1)


def test_sample_renders_with_chaos_and_prr(spirals):
    assert spirals.polar and spirals.classify() == "locally-contractive"
    chaos = ifsforge.render(spirals, "chaos", 128, binary=True, iterations=4_000_000)
    prr = ifsforge.render(spirals, "prr", 128, binary=True)
    iou = (chaos.mask & prr.mask).sum() / (chaos.mask | prr.mask).sum()
    assert chaos.covered() > 3000 and iou > 0.9
    assert np.array_equal(ifsforge.render(spirals, "chaos", 96, threads=1).density,
                          ifsforge.render(spirals, "chaos", 96, threads=2).density)
    with pytest.raises(ifsforge.InputError, match="does not render polar maps.*use chaos or prr"):
        ifsforge.render(spirals, "dia", 64)


def test_json_round_trip_is_exact(spirals):
    again = ifsforge.parse_json(ifsforge.to_json(spirals))
    assert again.polar_maps == spirals.polar_maps
    assert ifsforge.to_json(again) == ifsforge.to_json(spirals)


@pytest.mark.parametrize("polar, message", [
    ({"center": [0, 0], "k": 0, "F": [0] * 6, "G": [0] * 4}, "/maps/0/polar/k"),
    ({"center": [0, 0], "k": 1, "F": [0] * 5, "G": [0] * 4}, "/maps/0/polar/F: expected 6 numbers"),
    ({"center": [0, 0], "k": 1, "F": [0] * 6, "G": [0] * 7}, "/maps/0/polar/G: expected 4 numbers"),
    ({"center": [0, 0], "k": 1, "F": [0] * 6, "G": [0] * 4, "winding": 9}, "/maps/0/polar/winding"),
])
def test_bad_polar_maps_name_the_field(polar, message):
    text = json.dumps({"format": "ifsforge/1", "maps": [{"polar": polar}, {"polar": polar}]})
    with pytest.raises(ifsforge.InputError, match=message):
        ifsforge.parse_json(text)
    with pytest.raises(ifsforge.InputError, match="k must be greater than 0|not a finite number"):
        ifsforge.PolarMap((0, 0), float("nan"), F=[0] * 6, G=[0] * 4)


def test_info_reports_local_contraction(cli, samples):
    path = samples / "polar_spirals.json"
    info = json.loads(cli("info", path, "--json", check=True).stdout)
    system = ifsforge.read_json(str(path))
    assert [m["contraction_factor"] for m in info["maps"]] == [p.contraction() for p in system.polar_maps]
    assert info["classification"] == "locally-contractive" and "polar" in info["maps"][0]
    assert info["lyapunov_exponent"] is None  # the shadows' linear parts say nothing of the maps
    assert "(local, about P=(0, 0.8), Eq. 30)" in cli("info", path, check=True).stdout


def test_breed_cli_writes_a_sheet_and_systems_that_rerender(cli, tmp_path):
    cli("breed", "--count", 4, "--seed", 5, "--size", 64, "-o", "sheet.png", check=True)
    files = sorted((tmp_path / "sheet").glob("phenotype_*.json"))
    assert [f.name for f in files] == [f"phenotype_{k:02d}.json" for k in range(4)]
    sheet = ifsforge.read_png(str(tmp_path / "sheet.png"))
    assert sheet.shape[1] == 4 * 64 and sheet.max() > 0.5
    bred = ifsforge.breed(count=4, seed=5)
    for f, system in zip(files, bred):
        again = ifsforge.read_json(str(f))
        assert again.polar_maps == system.polar_maps  # deterministic for the seed
        assert all(m.contraction() <= 0.9 for m in again.polar_maps)
        assert ifsforge.render(again, "chaos", 64, binary=True).covered() > 0.1 * 64 * 64 * 0.5
    cli("breed", "--count", 4, "--seed", 5, "--size", 64, "-o", "again.png", check=True)
    assert (tmp_path / "again.png").read_bytes() == (tmp_path / "sheet.png").read_bytes()
    bad = cli("breed", "--count", 2, "--maps", 1, "-o", "one.png")
    assert bad.returncode == 2 and "maps" in bad.stderr and not (tmp_path / "one.png").exists()
