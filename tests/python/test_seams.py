"""Where the paths meet: every random-iteration path follows a recurrent system's transitions
(one walker), every renderer, volume renderer and sampler declares the systems it handles and
refuses the others by name, and the deterministic algorithms bound their work before they start."""
import json
import time

import numpy as np
import pytest

import ifsforge
from conftest import SAMPLES, patience

core = ifsforge._core
FLAGS = {"recurrent", "polar", "average_contractive", "overlapping", "condensation", "2d", "3d"}
# Three half-size Sierpinski maps and one expanding by 1.25 (p = 0.1): average-contractive (Eq. 14).
EXPANDING = {"format": "ifsforge/1", "name": "expanding", "layout": "xy", "maps": [
    {"matrix": [[0.5, 0], [0, 0.5]], "offset": [0, 0], "probability": 0.3},
    {"matrix": [[0.5, 0], [0, 0.5]], "offset": [0.5, 0], "probability": 0.3},
    {"matrix": [[0.5, 0], [0, 0.5]], "offset": [0.25, 0.5], "probability": 0.3},
    {"matrix": [[1.25, 0], [0, 1.25]], "offset": [-0.1, -0.075], "probability": 0.1}]}


@pytest.fixture(scope="module")
def squares():
    return ifsforge.load(str(SAMPLES / "recurrent_squares.json"))


def cells(points, n=32):
    """The cells of side 1/n of the unit square that points fall in, as an image mask (row 0 on top)."""
    x, y = points[:, 0], points[:, 1]
    keep = (x >= 0) & (x < 1) & (y > 0) & (y <= 1)
    mask = np.zeros((n, n), bool)
    mask[((1 - y[keep]) * n).astype(int), (x[keep] * n).astype(int)] = True
    return mask


def test_every_random_path_covers_the_recurrent_squares_like_chaos(squares):
    # 4 * 3^4 = 324 of the 1,024 cells hold an allowed address of length 5; before the one
    # walker, colour stealing, sample_points and preview_cloud filled all 1,024.
    chaos = ifsforge.render(squares, "chaos", 32, window=(0, 0, 1, 1), binary=True).mask
    assert chaos.sum() == 324
    picture = np.full((8, 8, 3), 0.5, np.float32)
    stolen = ifsforge.render(squares, "color-stealing", 32, window=(0, 0, 1, 1), reference_image=picture).mask
    assert (stolen == chaos).all()
    assert (cells(squares.sample_points(200_000, seed=3)) == chaos).all()
    # The cloud's float32 positions may round a point onto a cell's edge (runs of maps that add
    # no binary digit bring points within 2^-24 of one): each lies within 1e-6 of a chaos cell.
    points = ifsforge.preview_cloud(squares, 200_000).positions.astype(np.float64)
    assert (cells(points) >= chaos).all()
    near = np.zeros(len(points), bool)
    for dx in (-1e-6, 1e-6):
        for dy in (-1e-6, 1e-6):
            x, y = points[:, 0] + dx, points[:, 1] + dy
            inside = (x >= 0) & (x < 1) & (y > 0) & (y <= 1)
            row, col = ((1 - y[inside]) * 32).astype(int), (x[inside] * 32).astype(int)
            near[np.flatnonzero(inside)[chaos[row, col]]] = True
    assert near.all()


def test_capabilities_are_listed_for_every_algorithm():
    renderers = core.renderer_capabilities()
    assert list(renderers) == [name for name, _ in ifsforge.renderers()]
    for name, flags in renderers.items():
        assert set(flags) == FLAGS, name
    assert renderers["chaos"]["recurrent"] and renderers["chaos"]["polar"] and renderers["chaos"]["3d"]
    assert not renderers["prr"]["recurrent"] and renderers["prr"]["polar"]
    assert not renderers["string-rewriting"]["average_contractive"]
    volumes = core.volume_renderer_capabilities()
    assert list(volumes) == [name for name, _ in ifsforge.volume_renderers()]
    assert [name for name, flags in volumes.items() if flags["recurrent"]] == ["ria"]
    assert all(flags["3d"] and not flags["2d"] for flags in volumes.values())
    samplers = core.sampler_capabilities()
    assert samplers["sample_points"]["polar"] and not samplers["preview_cloud"]["polar"]


def test_a_refusal_names_the_renderers_that_draw_the_system(squares):
    features = squares.features()
    assert features["recurrent"] and not features["overlapping"]
    handles = [name for name, flags in core.renderer_capabilities().items() if flags["recurrent"]]
    assert "chaos" in handles and "prr" not in handles
    with pytest.raises(ifsforge.InputError) as refused:
        ifsforge.render(squares, "prr", 32)
    message = str(refused.value)
    assert "does not follow transitions" in message
    assert message.endswith("use " + ", ".join(handles[:-1]) + " or " + handles[-1])


def test_volumes_of_a_recurrent_system_follow_its_transitions_or_refuse():
    # 8 * 7^4 = 19,208 of the 32^3 cells hold an allowed address of length 5: random iteration
    # gave all 32,768 before it followed the transitions, and prr, dia and eta gave them too.
    cubes = ifsforge.load(str(SAMPLES / "recurrent_cubes.json"))
    box = (0, 0, 0, 1, 1, 1)
    assert len(ifsforge.render_volume(cubes, "ria", 32, bounds=box, iterations=4_000_000)) == 19208
    for name in ("prr", "dia", "eta"):
        with pytest.raises(ifsforge.InputError, match=f"volume algorithm '{name}' does not follow transitions.*use ria$"):
            ifsforge.render_volume(cubes, name, 32, bounds=box)


def test_an_average_contractive_system_is_refused_by_the_deterministic_algorithms(cli, tmp_path):
    # These ran into unbounded memory (0.6 -> 3 GB in 68 s) and did not hear Ctrl-C.
    (tmp_path / "expanding.json").write_text(json.dumps(EXPANDING))
    system = ifsforge.load(str(tmp_path / "expanding.json"))
    assert system.classify() == "average-contractive" and system.features()["average_contractive"]
    for name in ("string-rewriting", "probabilistic-domain"):
        start = time.perf_counter()
        result = cli("render", "expanding.json", "-a", name, "--size", "32", "-o", "x.png")
        assert result.returncode == 2 and not (tmp_path / "x.png").exists()
        assert f"'{name}' needs every map to contract" in result.stderr and "use chaos" in result.stderr
        assert time.perf_counter() - start < patience(10)
    assert ifsforge.render(system, "chaos", 32, iterations=100_000).covered() > 100


def test_overlapping_pieces_are_counted_before_the_work():
    # Four maps of 0.6 into the corners: a filled square whose pieces overlap (sum |det| = 1.44).
    square = ifsforge.Ifs([ifsforge.AffineMap(np.eye(2) * 0.6, [x, y]) for x in (0, 0.4) for y in (0, 0.4)],
                          name="overlapping square")
    assert square.features()["overlapping"]
    start = time.perf_counter()
    with pytest.raises(ifsforge.InputError, match="afra would split system 'overlapping square' into 10\\^"):
        ifsforge.render(square, "afra", 2048)
    assert time.perf_counter() - start < patience(2)
    small = ifsforge.render(square, "afra", 32, window=(0, 0, 1, 1), binary=True)
    assert small.covered() == 32 * 32
