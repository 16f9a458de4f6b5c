"""The memory budget held where memory is taken: PNG readers check a header's declared size before
inflating a row, decoders and frame loops estimate before working, and every command refuses
under a small budget with its peak memory measured (the budget plus the interpreter's own)."""
import struct
import time
import zlib

import pytest

from conftest import SAMPLES, patience
from test_hostile import BUDGET_MB, hostile

import ifsforge

SIERPINSKI = SAMPLES / "sierpinski_triangle.json"
FERN = SAMPLES / "barnsley_fern.json"
# What the interpreter, numpy and the module take before any work: peak RSS may exceed the
# budget by this much.
INTERPRETER_MB = 64


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png(width, height, rows=b""):
    """A gray 8-bit PNG declaring width x height, with `rows` (filter bytes included) as its data."""
    head = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", head) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")


def refused_within_budget(tmp_path, *args, names=("budget",)):
    code, err, peak = hostile(tmp_path, *args)
    assert code == 2 and "Traceback" not in err, err
    for name in names:
        assert name in err, err
    assert peak < BUDGET_MB + INTERPRETER_MB, f"peak {peak:.0f} MB"
    return err


@pytest.fixture
def huge_header(tmp_path):
    """68 bytes declaring 10^6 x 10^6 pixels."""
    path = tmp_path / "huge.png"
    path.write_bytes(png(1000000, 1000000))
    return path


@pytest.fixture
def inflating(tmp_path):
    """A decompression bomb: 16000^2 zero pixels (256 MB) in a few hundred kilobytes."""
    side = 16000
    rows = (b"\x00" + bytes(side)) * side
    path = tmp_path / "bomb.png"
    path.write_bytes(png(side, side, rows))
    assert path.stat().st_size < 400_000
    return path


@pytest.mark.parametrize("command", [
    ["collage", SIERPINSKI, "{png}"],
    ["fit", "{png}", "-o", "f.json"],
    ["compress", "{png}", "-o", "c.pifs"],
    ["palette", SAMPLES.parent / "terrain" / "ember_hls.json", "--apply", "{png}", "out.png"],
    ["terrain", "-o", "t.png", "--heights-from", "{png}"],
    ["render", SIERPINSKI, "-o", "r.png", "--reference", "{png}"],
    ["warp", "{png}", "--from", SIERPINSKI, "--to", SIERPINSKI, "-o", "w.png"],
])
@pytest.mark.parametrize("picture", ["huge_header", "inflating"])
def test_every_png_reader_checks_the_declared_size_first(tmp_path, command, picture, request):
    path = request.getfixturevalue(picture)
    args = [str(a).replace("{png}", str(path)) for a in command]
    err = refused_within_budget(tmp_path, *args, names=("budget", path.name))
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name], "an output was left"
    assert "x" in err  # the declared size is named


def test_decompress_estimates_the_output_before_decoding(tmp_path):
    image = ifsforge.render(ifsforge.load(str(SIERPINSKI)), "chaos", 64)
    ifsforge.write_png(str(tmp_path / "s.png"), image)
    ifsforge.write_pifs(str(tmp_path / "s.pifs"), ifsforge.pifs_encode(ifsforge.read_png(str(tmp_path / "s.png"))))
    refused_within_budget(tmp_path, "decompress", "s.pifs", "-o", "d.png", "--size", "8000", "8000",
                          names=("8000x8000",))
    refused_within_budget(tmp_path, "decompress", "s.pifs", "-o", "d.png", "--scale", "1024",
                          names=("65535",))
    assert not (tmp_path / "d.png").exists()


@pytest.mark.parametrize("args, names", [
    (["palette", SAMPLES.parent / "terrain" / "ember_hls.json", "-o", "p.png", "--entries", "65536", "--rows", "4096"],
     ("65536x4096",)),
    (["breed", "--count", "4096", "--size", "4096", "-o", "sheet.png"], ("4096 phenotypes",)),
    (["interpolate", "--x", "0", "1", "2", "--values", "0", "1", "0", "--a22", "0.5", "-o", "f.csv",
      "--samples", "100000000"], ("CSV rows",)),
])
def test_generators_estimate_and_refuse_before_working(tmp_path, args, names):
    refused_within_budget(tmp_path, *args, names=names)
    assert not any(tmp_path.iterdir())


def test_morph_streams_its_frames(tmp_path):
    # Thousands of JSON frames under a small budget: each system is made, written and dropped.
    code, err, peak = hostile(tmp_path, "morph", SIERPINSKI, SIERPINSKI, "-o", "frames", "--frames", "3000", "--json")
    assert code == 0, err
    assert len(list((tmp_path / "frames").iterdir())) == 3000
    assert peak < BUDGET_MB + INTERPRETER_MB, f"peak {peak:.0f} MB"


@pytest.mark.long
def test_warp_streams_its_frames(tmp_path):
    # Each frame is written and dropped: the peak does not grow with the frame count. 400 RGBA
    # float frames of 256^2 (1 MiB each) kept would pass the budget; one chaos-game point per
    # pixel draws each frame (the default, rounds until the attractor is found, costs ten times
    # more and holds no more memory: the frame's array is its size whatever the points).
    target = tmp_path / "target.png"
    target.write_bytes(png(64, 64, (b"\x00" + bytes(range(64))) * 64))
    code, err, peak = hostile(tmp_path, "warp", target, "--from", SIERPINSKI, "--to", SIERPINSKI, "-o", "frames",
                              "--frames", "400", "--size", "256", "--iterations", str(256 * 256))
    assert code == 0, err
    assert len(list((tmp_path / "frames").iterdir())) == 400
    assert peak < BUDGET_MB + INTERPRETER_MB, f"peak {peak:.0f} MB"


def test_restarts_must_be_at_least_one_in_python_too():
    import numpy as np
    with pytest.raises(ifsforge.InputError, match="restarts"):
        ifsforge.fit(np.ones((32, 32), bool), maps=2, restarts=0)
    with pytest.raises(ifsforge.InputError, match="restarts"):
        ifsforge.fit_3d(np.ones((8, 8, 8), bool), (0.0, 0.0, 0.0), 1.0, maps=2, restarts=0)


def test_a_pruned_instance_tree_is_estimated_before_it_is_walked(tmp_path):
    # Depth 60 pruned at 10^-12: tens of billions of the fern's leaves. Their count is bounded
    # from the map probabilities alone, and the walk is never started.
    start = time.monotonic()
    err = refused_within_budget(tmp_path, "instances", FERN, "--depth", "60", "--min-probability", "1e-12",
                                "--pov", "t.pov", names=("--depth", "--min-probability", "instances"))
    assert time.monotonic() - start < patience(5.0)
    assert not any(tmp_path.iterdir())
    assert "at least" in err


def test_python_instances_refuse_the_same_tree(monkeypatch):
    monkeypatch.setenv("IFSFORGE_MEMORY_BUDGET_MB", str(BUDGET_MB))
    fern = ifsforge.load(str(FERN))
    with pytest.raises(ifsforge.MemoryBudgetError, match="min-probability"):
        ifsforge.instances(fern, depth=60, min_probability=1e-9)
    with pytest.raises(ifsforge.InputError, match="more than 10\\^12"):
        ifsforge.instances(fern, depth=60, min_probability=1e-12)
    with pytest.raises(ifsforge.InputError, match="more than 10\\^12"):
        ifsforge.count_leaves(fern, 60, 1e-13)
    # A tree the budget holds is built, with exactly the leaves counted.
    small = ifsforge.instances(fern, depth=60, min_probability=1e-4)
    assert len(small) == ifsforge.count_leaves(fern, 60, 1e-4)
