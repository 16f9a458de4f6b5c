"""The command line: it works on good input, and on bad input says why, exits non-zero and
writes nothing."""
import json
import os
import subprocess

import numpy as np
import pytest

import ifsforge
from conftest import BUILD_PYTHON

TRIANGLE = {"format": "ifsforge/1", "name": "triangle", "layout": "xy", "probabilities": "uniform",
            "maps": [{"matrix": [[0.5, 0], [0, 0.5]], "offset": o} for o in ([0, 0], [0.5, 0], [0.25, 0.5])]}


def write(path, data):
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return path


def test_render_info_convert(cli, tmp_path):
    system = write(tmp_path / "t.json", TRIANGLE)
    out = tmp_path / "t.png"
    cli("render", system, "-o", out, "--size", "128", "--algorithm", "prr", check=True)
    image = ifsforge.read_png(str(out))
    assert image.shape == (128, 128) and image.max() == 1.0
    info = json.loads(cli("info", system, "--json", check=True).stdout)
    assert info["classification"] == "hyperbolic"
    assert info["box_counting_dimension"] == pytest.approx(np.log(3) / np.log(2), rel=0.03)
    assert info["maps"][1]["fixed_point"] == pytest.approx([1.0, 0.0])
    library = write(tmp_path / "lib.ifs", "a { 0.5 0 0 0.5 0 0 1\n 0.5 0 0 0.5 0.5 0 1 }\nb (3D) {\n"
                    + "\n".join(f".5 0 0 0 .5 0 0 0 .5 {x} {y} {z} 1" for x, y, z in ((0, 0, 0), (.5, 0, 0), (0, .5, 0), (0, 0, .5)))
                    + "\n}\n")
    cli("convert", library, "-o", tmp_path / "json", check=True)
    assert sorted(p.name for p in (tmp_path / "json").iterdir()) == ["a.json", "b_3d.json"]
    assert ifsforge.read_json(str(tmp_path / "json" / "b_3d.json")).dim == 3
    cli("render", f"{library}:b (3D)", "-o", tmp_path / "b.png", "--size", "64", check=True)
    assert ifsforge.read_png(str(tmp_path / "b.png")).max() > 0


BAD = {
    "malformed.json": ('{"maps": [', "malformed JSON"),
    "types.json": ({"maps": [{"matrix": "identity", "offset": [0, 0]}]}, "/maps/0/matrix"),
    "rows.ifs": ("x {\n 0.5 0 0 0.5 0 0\n}\n", "7 numbers, found 6"),
    "zero.json": ({**TRIANGLE, "probabilities": None,
                   "maps": [{**m, "probability": 0} for m in TRIANGLE["maps"]]}, "positive"),
    "nan.ifs": ("x {\n nan 0 0 0.5 0 0 1\n}\n", "NaN"),
    "divergent.json": ({"name": "grow", "maps": [{"matrix": [[1.5, 0], [0, 1.5]], "offset": [0, 0]}]}, "divergent"),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_bad_input_is_refused_cleanly(cli, tmp_path, name):
    data, message = BAD[name]
    if isinstance(data, dict):
        data = {k: v for k, v in data.items() if v is not None}
    system = write(tmp_path / name, data)
    out = tmp_path / "out.png"
    result = cli("render", system, "-o", out, "--size", "32")
    assert result.returncode == 2, result.stderr
    assert message in result.stderr
    assert "Traceback" not in result.stderr
    assert not out.exists() and list(tmp_path.glob("out.png*")) == []


def test_absurd_size_and_unwritable_path(cli, tmp_path):
    system = write(tmp_path / "t.json", TRIANGLE)
    result = cli("render", system, "-o", tmp_path / "big.png", "--size", "65535", "--threads", "2")
    if result.returncode == 0:  # a machine with > 90 GB would render it; this one must refuse
        pytest.fail("a 65535^2 render on two threads should exceed the memory budget")
    assert "memory" in result.stderr and not (tmp_path / "big.png").exists()
    result = cli("render", system, "-o", "/proc/forbidden/x.png", "--size", "32")
    assert result.returncode == 2 and "cannot write" in result.stderr
    result = cli("render", system, "-o", tmp_path / "x.png", "--size", "0")
    assert result.returncode == 2 and "--size" in result.stderr
    result = cli("render", tmp_path / "missing.json", "-o", tmp_path / "x.png")
    assert result.returncode == 2 and "cannot read" in result.stderr


def info_of(cli, system):
    """`ifsforge info` twice: the printed text and the --json dict."""
    text = cli("info", system, check=True).stdout
    return text, json.loads(cli("info", system, "--json", check=True).stdout)


def test_info_shows_the_transition_matrix(cli, samples):
    path = samples / "recurrent_squares.json"
    rows = np.array(json.loads(path.read_text())["transitions"], dtype=float)
    rows /= rows.sum(axis=1, keepdims=True)  # the file gives weights; rows are normalised on load
    text, info = info_of(cli, path)
    np.testing.assert_allclose(info["transitions"], rows, atol=1e-12)
    lines = text.splitlines()
    header = lines.index("transitions (row i: probability that map j follows map i):")
    assert lines[header + 1].split() == ["map", "1", "map", "2", "map", "3", "map", "4"]
    for i, row in enumerate(rows, 1):
        label, number, *values = lines[header + 1 + i].split()
        assert (label, number) == ("map", str(i))
        np.testing.assert_allclose([float(v) for v in values], row, atol=5e-5)  # printed to 4 places
    # Every map has three successors, so the stationary distribution, which the maps' probabilities
    # become, is uniform.
    assert [m["probability"] for m in info["maps"]] == pytest.approx([0.25] * 4)


def test_info_shows_the_super_ifs_members(cli, samples):
    path = samples / "superfractal_pair.json"
    data = json.loads(path.read_text())
    text, info = info_of(cli, path)
    parts = info["super_ifs"]
    assert parts["variability"] == data["variability"]
    members = parts["members"]
    assert [m["name"] for m in members] == [s["name"] for s in data["systems"]]
    assert sum(m["probability"] for m in members) == pytest.approx(1.0)
    assert [m["map_count"] for m in members] == [len(s["maps"]) for s in data["systems"]]
    assert sum(m["map_count"] for m in members) == len(info["maps"])
    for member, system in zip(members, data["systems"]):
        assert member["map_probabilities"] == pytest.approx([m["probability"] for m in system["maps"]])
        # Eq. 38: map m of member n is chosen with probability P_n p_nm.
        union = [info["maps"][i]["probability"] for i in member["map_indices"]]
        assert union == pytest.approx([member["probability"] * p for p in member["map_probabilities"]])
    assert "super IFS: 2 member systems, variability V=2" in text
    assert "member 1 'spreading tree': P=0.5000  3 maps (maps 1-3, p=0.1000 0.4500 0.4500)" in text
    assert "member 2 'upright tree': P=0.5000  3 maps (maps 4-6, p=0.1000 0.4500 0.4500)" in text


def test_info_shows_the_condensation_set(cli, samples, tmp_path):
    path = samples / "condensation_tree.json"
    data = json.loads(path.read_text())
    text, info = info_of(cli, path)
    c = info["condensation"]
    trunk = np.array(data["condensation"]["polygons"][0])
    assert c["polygons"] == [len(trunk)] and c["polylines"] == []
    assert c["probability"] == data["condensation"]["probability"]
    assert c["bounds"] == pytest.approx([*trunk.min(axis=0), *trunk.max(axis=0)])
    assert c["channels"] == {}
    # The attractor holds C and the maps' attractor, whose sampled bounds are also printed.
    box, sampled = c["attractor_box"], info["bounds"]
    assert box[0] <= min(c["bounds"][0], sampled["x"][0]) and box[2] >= max(c["bounds"][2], sampled["x"][1])
    assert box[1] <= min(c["bounds"][1], sampled["y"][0]) and box[3] >= max(c["bounds"][3], sampled["y"][1])
    assert "condensation set: 1 polygon (4 points), 0 polylines, p0=0.2000" in text
    assert "  box: x [-0.06, 0.06]  y [0, 1.12]" in text
    # A coloured layout: the set carries a value of each extra channel.
    coloured = {**TRIANGLE, "layout": "xy+rgb",
                "maps": [{"matrix": (0.5 * np.eye(5)).tolist(), "offset": [*o, 0.2, 0.4, 0.6]}
                         for o in ([0, 0], [0.5, 0], [0.25, 0.5])],
                "condensation": {"polylines": [[[0, 0], [1, 0]]], "channels": [1.0, 0.5, 0.25], "probability": 0.1}}
    text, info = info_of(cli, write(tmp_path / "c.json", coloured))
    assert info["condensation"]["channels"] == {"r": 1.0, "g": 0.5, "b": 0.25}
    assert info["condensation"]["polylines"] == [2] and info["condensation"]["polygons"] == []
    assert "condensation set: 0 polygons, 1 polyline (2 points), p0=0.1000" in text
    assert "  channels: r=1  g=0.5  b=0.25" in text


def test_info_of_an_ordinary_system_has_no_extensions(cli, tmp_path):
    text, info = info_of(cli, write(tmp_path / "t.json", TRIANGLE))
    assert not {"transitions", "super_ifs", "condensation"} & info.keys()
    assert "transitions" not in text and "super IFS" not in text and "condensation" not in text


# The CLI with numpy's import refused: what a command imports is what its start-up costs.
WITHOUT_NUMPY = ("import sys\n"
                 "class NoNumpy:\n"
                 "    def find_spec(self, name, path, target=None):\n"
                 "        if name.split('.')[0] == 'numpy': raise ImportError('numpy imported')\n"
                 "sys.meta_path.insert(0, NoNumpy())\n"
                 "from ifsforge.cli import main\n"
                 "sys.exit(main())\n")


def test_render_writes_its_png_without_importing_numpy(tmp_path):
    # numpy's import would be most of a small render's time: the CLI tone-maps and
    # writes the raster in the core. The same bytes as the numpy path of the Python API.
    system = write(tmp_path / "t.json", TRIANGLE)
    out = tmp_path / "t.png"
    args = ["render", str(system), "-o", str(out), "--size", "96", "--iterations", "5000", "--mode", "density"]
    result = subprocess.run(["/usr/bin/python3", "-c", WITHOUT_NUMPY, *args], capture_output=True, text=True,
                            env=dict(os.environ, PYTHONPATH=str(BUILD_PYTHON)))
    assert result.returncode == 0, result.stderr
    raster = ifsforge.render(ifsforge.read_json(str(system)), "chaos", 96, iterations=5000)
    ifsforge.write_png(str(tmp_path / "api.png"), raster.to_image("density"))
    assert out.read_bytes() == (tmp_path / "api.png").read_bytes()


def test_info_reports_without_importing_numpy(tmp_path):
    system = write(tmp_path / "t.json", TRIANGLE)
    result = subprocess.run(["/usr/bin/python3", "-c", WITHOUT_NUMPY, "info", str(system), "--json"], capture_output=True,
                            text=True, env=dict(os.environ, PYTHONPATH=str(BUILD_PYTHON)))
    assert result.returncode == 0, result.stderr
    info = json.loads(result.stdout)
    assert info["maps"][2]["fixed_point"] == pytest.approx([0.5, 1.0])
    assert info["maps"][0]["matrix"] == [[0.5, 0.0], [0.0, 0.5]] and info["contraction_ratio"] == 0.5
    assert info["bounds"]["x"] == pytest.approx([0.0, 1.0], abs=1e-6)
