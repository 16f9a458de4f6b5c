"""Design helpers through Python and the CLI: preview clouds (the binding: shapes, dtypes,
no-copy views, determinism) and morphs (end points, continuity, the `morph` command)."""
import json

import numpy as np
import pytest

import ifsforge

TRIANGLE = {"format": "ifsforge/1", "name": "triangle", "layout": "xy", "probabilities": "uniform",
            "maps": [{"matrix": [[0.5, 0], [0, 0.5]], "offset": o} for o in ([0, 0], [0.5, 0], [0.25, 0.5])]}
SQUARE = {"format": "ifsforge/1", "name": "square", "layout": "xy", "probabilities": "uniform",
          "maps": [{"scale": [0.5, 0.5], "rotation": 30, "translation": o}
                   for o in ([0, 0], [0.5, 0], [0, 0.5], [0.5, 0.5])]}


def test_preview_cloud_arrays(samples):
    fern = ifsforge.load(str(samples / "barnsley_fern.json"))
    cloud = ifsforge.preview_cloud(fern, 50000, seed=3, highlight=1)
    assert cloud.coloring == "pieces"
    assert cloud.positions.shape == (50000, 3) and cloud.positions.dtype == np.float32
    assert cloud.colors.shape == (50000, 4) and cloud.pieces.dtype == np.uint32
    assert not cloud.positions.flags.writeable  # a view of the cloud's memory, not a copy
    assert (cloud.positions[:, 2] == 0).all()
    lo, hi = cloud.bounds
    assert lo.shape == (2,) and np.all(cloud.positions[:, :2] >= lo.astype(np.float32) - 1e-6)
    # The fern's pieces: frequencies follow its probabilities (0.01, 0.85, 0.07, 0.07).
    freq = np.bincount(cloud.pieces, minlength=4) / 50000
    np.testing.assert_allclose(freq, fern.probabilities, atol=0.01)
    # Only the highlighted map's piece is at full brightness.
    bright = np.array([ifsforge.piece_color(i) for i in range(4)], np.float32)
    dim = np.array([ifsforge.piece_color(i, True) for i in range(4)], np.float32)
    expected = np.where((cloud.pieces == 1)[:, None], bright[cloud.pieces], dim[cloud.pieces])
    np.testing.assert_array_equal(cloud.colors, expected)
    # The box and four frames of 4 edges, 2 end points each.
    assert cloud.frame_positions.shape == (5 * 8, 3) and set(cloud.frame_pieces) == {0, 1, 2, 3, 4}
    again = ifsforge.preview_cloud(fern, 50000, seed=3, highlight=1, threads=1)
    np.testing.assert_array_equal(again.positions, cloud.positions)


def test_preview_cloud_errors():
    grow = ifsforge.Ifs([ifsforge.AffineMap([[1.3, 0], [0, 1.3]], [0, 0])], name="grow")
    with pytest.raises(ifsforge.DivergentSystemError, match="grow"):
        ifsforge.preview_cloud(grow)
    triangle = ifsforge.parse_json(json.dumps(TRIANGLE))
    with pytest.raises(ifsforge.InputError, match="color"):
        ifsforge.preview_cloud(triangle, coloring="channels")
    with pytest.raises(ifsforge.InputError, match="rainbow"):
        ifsforge.preview_cloud(triangle, coloring="rainbow")


def test_morph_in_python():
    a, b = ifsforge.parse_json(json.dumps(TRIANGLE)), ifsforge.parse_json(json.dumps(SQUARE))
    start, end = ifsforge.morph(a, b, 0.0), ifsforge.morph(a, b, 1.0)
    assert len(start) == 4  # padded: the triangle's last map twice, same attractor
    np.testing.assert_array_equal(start.maps[3].matrix, a.maps[2].matrix)
    np.testing.assert_allclose(start.probabilities, [1 / 3, 1 / 3, 1 / 6, 1 / 6])
    for m, n in zip(end.maps, b.maps):
        np.testing.assert_array_equal(m.matrix, n.matrix)
    # Halfway: scale 0.5 and rotation 15 degrees (from 0 to 30), translation halfway.
    half = ifsforge.morph(a, b, 0.5)
    c, s = 0.5 * np.cos(np.radians(15)), 0.5 * np.sin(np.radians(15))
    np.testing.assert_allclose(half.maps[1].matrix, [[c, -s], [s, c]], atol=1e-12)
    np.testing.assert_allclose(half.maps[1].offset, [0.5, 0])
    with pytest.raises(ifsforge.InputError, match="layouts differ"):
        ifsforge.morph(a, ifsforge.Ifs([ifsforge.AffineMap(np.eye(3) * 0.5, [0, 0, 0])], layout="xyz"), 0.5)


def test_morph_command(cli, tmp_path):
    (tmp_path / "a.json").write_text(json.dumps(TRIANGLE))
    (tmp_path / "b.json").write_text(json.dumps(SQUARE))
    cli("morph", tmp_path / "a.json", tmp_path / "b.json", "-o", tmp_path / "json", "--frames", "5", "--json",
        check=True)
    systems = [ifsforge.read_json(str(tmp_path / "json" / f"morph_{k:04d}.json")) for k in range(5)]
    np.testing.assert_allclose(systems[4].maps[0].matrix, ifsforge.parse_json(json.dumps(SQUARE)).maps[0].matrix,
                               atol=1e-12)
    cli("morph", tmp_path / "a.json", tmp_path / "b.json", "-o", tmp_path / "png", "--frames", "3", "--size", "64",
        check=True)
    frames = [ifsforge.read_png(str(tmp_path / "png" / f"morph_{k:04d}.png")) for k in range(3)]
    assert all(f.shape == (64, 64) and f.max() > 0 for f in frames)
    assert not np.array_equal(frames[0], frames[2])
    # A morph into a divergent system is refused before any frame is written.
    grow = dict(TRIANGLE, name="grow", maps=[{"matrix": [[1.5, 0], [0, 1.5]], "offset": [0, 0]}] * 3)
    (tmp_path / "grow.json").write_text(json.dumps(grow))
    result = cli("morph", tmp_path / "a.json", tmp_path / "grow.json", "-o", tmp_path / "bad", "--frames", "4")
    assert result.returncode == 2 and "no attractor" in result.stderr
    assert not (tmp_path / "bad").exists() or not any((tmp_path / "bad").iterdir())
