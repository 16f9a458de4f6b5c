"""Fractal image compression (seed 3.3.2) from Python and the CLI: numpy in and out, files,
decoding at any size, rate control, thread-independent bytes, bad files refused without output."""
import json
import warnings

import numpy as np
import pytest

import ifsforge
from conftest import patience
from test_hostile import interrupt_after


def textured(h, w, channels=1):
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    layers = [0.5 + 0.3 * np.sin(x / (7 + c)) * np.cos(y / 11) + 0.12 * np.sin((x + 2 * y) / 3 + c)
              for c in range(channels)]
    image = np.stack(layers, axis=-1) if channels > 1 else layers[0]
    return np.round(np.clip(image, 0, 1) * 255).astype(np.uint8)


def psnr(a, b):
    return 10 * np.log10(1.0 / np.mean((np.asarray(a, np.float64) - b) ** 2))


def test_constant_image_round_trips_exactly():
    image = np.full((33, 47), 91, np.uint8)
    out = ifsforge.pifs_encode(image).decode()
    assert out.shape == (33, 47)
    assert np.array_equal(np.round(out * 255).astype(np.uint8), image)


def test_encode_decode_any_size_and_bytes_round_trip():
    image = textured(70, 90, 3)
    code = ifsforge.pifs_encode(image, quality=2)
    assert (code.width, code.height, code.channels, code.color) == (90, 70, 3, "ycbcr420")
    assert code.plane_sizes == [(90, 70), (45, 35), (45, 35)]
    out = code.decode()
    assert out.shape == (70, 90, 3) and out.dtype == np.float32
    assert psnr(image / 255.0, out) > 27
    assert code.decode(size=(31, 200)).shape == (200, 31, 3)
    assert code.decode(scale=3).shape == (210, 270, 3)
    data = code.to_bytes()
    again = ifsforge.pifs_from_bytes(data)
    assert again.to_bytes() == data
    assert np.array_equal(again.decode(), out)
    cost = code.cost()
    assert cost["bytes"] == len(data)
    parts = ("header", "quadtree", "contrast", "mean", "isometry", "domain")
    assert sum(cost[f"{p}_bits"] for p in parts) == pytest.approx(8 * len(data), rel=0.02)


def test_two_times_averaged_matches_one_time():
    code = ifsforge.pifs_encode(textured(64, 96), ratio=10)
    one = code.decode(deblock=False)
    two = code.decode(scale=2, deblock=False, zoom="fractal")
    averaged = two.reshape(64, 2, 96, 2).mean(axis=(1, 3))
    assert psnr(one, averaged) > 30


def test_zoom_filter_averages_back_to_the_one_time_decode(cli, tmp_path):
    code = ifsforge.pifs_encode(textured(64, 96), ratio=10)
    one = code.decode()
    for scale in (2, 4):
        hybrid = code.decode(scale=scale)
        averaged = hybrid.reshape(64, scale, 96, scale).mean(axis=(1, 3))
        assert psnr(one, averaged) > 40
        assert not np.array_equal(hybrid, code.decode(scale=scale, zoom="fractal"))
    path = tmp_path / "t.pifs"
    ifsforge.write_pifs(str(path), code)
    pngs = {}
    for zoom in ("hybrid", "fractal"):
        cli("decompress", path, "-o", tmp_path / f"{zoom}.png", "--scale", "2", "--zoom", zoom, check=True)
        pngs[zoom] = ifsforge.read_png(str(tmp_path / f"{zoom}.png"))
        assert np.abs(pngs[zoom] - np.clip(code.decode(scale=2, zoom=zoom), 0, 1)).max() <= 0.5 / 255 + 1e-6
    assert not np.array_equal(pngs["hybrid"], pngs["fractal"])


def test_rgba_alpha_is_a_plane_and_threads_give_same_bytes(tmp_path):
    image = textured(50, 60, 4)
    one = ifsforge.pifs_encode(image, ratio=8, threads=1)
    two = ifsforge.pifs_encode(image, ratio=8, threads=2)
    assert one.to_bytes() == two.to_bytes()
    assert len(one.plane_sizes) == 4 and one.plane_sizes[3] == (60, 50)
    path = tmp_path / "a.pifs"
    ifsforge.write_pifs(str(path), one)
    assert path.read_bytes() == one.to_bytes()
    assert ifsforge.read_pifs(str(path)).decode().shape == (50, 60, 4)


def test_ratio_within_ten_percent():
    image = textured(128, 160)
    for ratio in (10, 30):
        size = len(ifsforge.pifs_encode(image, ratio=ratio).to_bytes())
        assert 0.9 * image.size / ratio <= size <= image.size / ratio


def test_sixteen_bit_input_is_reduced_with_a_warning():
    image = textured(40, 40).astype(np.uint16) * 257
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        code = ifsforge.pifs_encode(image, quality=2)
    assert any("16-bit" in str(w.message) for w in caught)
    assert psnr(image / 65535.0, code.decode()) > 30


def test_corrupt_bytes_refused():
    data = bytearray(ifsforge.pifs_encode(textured(40, 40), quality=4).to_bytes())
    with pytest.raises(ifsforge.InputError, match="truncated|corrupt"):
        ifsforge.pifs_from_bytes(bytes(data[:-5]))
    data[len(data) // 2] ^= 0xFF
    with pytest.raises(ifsforge.InputError, match="corrupt"):
        ifsforge.pifs_from_bytes(bytes(data))


def test_cli_compress_info_decompress(cli, tmp_path):
    source = tmp_path / "in.png"
    ifsforge.write_png(str(source), textured(100, 120, 3))
    out = tmp_path / "in.pifs"
    result = cli("compress", source, "-o", out, "--ratio", "20", check=True)
    assert "20.0:1" in result.stdout or "ratio" in result.stdout
    raw = 100 * 120 * 3
    assert 0.9 * raw / 20 <= out.stat().st_size <= raw / 20
    info = json.loads(cli("info", out, "--json", check=True).stdout)
    assert (info["width"], info["height"], info["channels"], info["bytes"]) == (120, 100, 3, out.stat().st_size)
    png = tmp_path / "big.png"
    cli("decompress", out, "-o", png, "--scale", "2", check=True)
    assert ifsforge.read_png(str(png)).shape == (200, 240, 3)
    cli("decompress", out, "-o", png, "--size", "50", "70", "--iterations", "20", "--decoder", "iterative",
        check=True)
    assert ifsforge.read_png(str(png)).shape == (70, 50, 3)


def test_exhaustive_search_from_python_and_cli(cli, tmp_path):
    # Every block of one size is a leaf (quality 0): the exhaustive search's fit of each is the
    # least-squares optimum, so its collage, and here its decode, is at least as close.
    image = textured(48, 64)
    options = dict(min_block=4, max_block=4, quality=0)
    tree = ifsforge.pifs_encode(image, **options)
    full = ifsforge.pifs_encode(image, search="exhaustive", **options)
    assert ifsforge.choices["search"] == ["tree", "exhaustive"]
    assert psnr(image / 255.0, full.decode(deblock=False)) >= psnr(image / 255.0, tree.decode(deblock=False)) - 0.05
    with pytest.raises(ValueError, match="exhaustive"):
        ifsforge.pifs_encode(image, search="everything")
    source, out = tmp_path / "in.png", tmp_path / "in.pifs"
    ifsforge.write_png(str(source), image)
    cli("compress", source, "-o", out, "--quality", "0", "--min-block", "4", "--max-block", "4",
        "--search", "exhaustive", check=True)
    assert out.read_bytes() == full.to_bytes()


def test_cli_sixteen_bit_message(cli, tmp_path):
    source = tmp_path / "deep.png"
    ifsforge.write_png(str(source), textured(40, 48) / 255.0, 16)
    result = cli("compress", source, "-o", tmp_path / "d.pifs", check=True)
    assert "16-bit" in result.stderr


@pytest.mark.parametrize("damage", ["truncate", "flip", "magic"])
def test_cli_refuses_bad_files_without_output(cli, tmp_path, damage):
    path = tmp_path / "bad.pifs"
    data = bytearray(ifsforge.pifs_encode(textured(48, 48), quality=4).to_bytes())
    if damage == "truncate":
        data = data[: len(data) // 2]
    elif damage == "flip":
        data[20] ^= 0x10
    else:
        data[:4] = b"JUNK"
    path.write_bytes(bytes(data))
    out = tmp_path / "out.png"
    result = cli("decompress", path, "-o", out)
    assert result.returncode == 2
    assert "bad.pifs" in result.stderr and ("corrupt" in result.stderr or "truncated" in result.stderr
                                            or "not a PIFS" in result.stderr)
    assert not out.exists()


def test_cli_refuses_unreachable_size(cli, tmp_path):
    source = tmp_path / "in.png"
    ifsforge.write_png(str(source), textured(64, 64) / 255.0)
    out = tmp_path / "x.pifs"
    result = cli("compress", source, "-o", out, "--bytes", "8")
    assert result.returncode == 2 and "cannot reach 8 bytes" in result.stderr
    assert not out.exists()


def test_camera_beats_jpeg_budget_at_100_to_1():
    data = pytest.importorskip("skimage.data")
    camera = data.camera()
    code = ifsforge.pifs_encode(camera, ratio=100)
    assert len(code.to_bytes()) <= camera.size // 100
    # Above what JPEG (Pillow, optimised) reaches at these bytes (cpp/bench/pifs_vs_jpeg.py).
    assert psnr(camera / 255.0, code.decode()) > 25.5


def test_ctrl_c_stops_compress_within_a_second(tmp_path):
    # A 3072^2 texture keeps the encoder busy for seconds: SIGINT must be heard inside its loops.
    rng = np.random.default_rng(5)
    image = textured(3072, 3072).astype(np.int16) + rng.integers(-20, 21, (3072, 3072))
    source = tmp_path / "big.png"
    ifsforge.write_png(str(source), np.clip(image, 0, 255).astype(np.uint8) / 255.0)
    code, err, stop = interrupt_after(tmp_path, 2.5, "compress", source, "-o", tmp_path / "big.pifs", "--ratio", "8")
    assert code == 130 and "interrupted" in err and "Traceback" not in err, err
    assert stop < patience(1.0), f"{stop:.1f} s to stop"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["big.png"]
