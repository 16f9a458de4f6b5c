"""The command line: it works on good input, and on bad input says why, exits non-zero and
writes nothing."""
import json

import numpy as np
import pytest

import ifsforge

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
