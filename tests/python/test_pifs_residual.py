"""The residual layer of fractal compression: quality that keeps rising with bytes (monotone
rate-distortion on a fixed image), the rate control still hitting the size, identical bytes on
any thread count, decoding at other scales, the CLI switch, and version-1 files still read."""
import json
from pathlib import Path

import numpy as np
import pytest

import ifsforge
from test_pifs import psnr, textured

DATA = Path(__file__).parent / "data"


def photo_like(h=96, w=128):
    """Smooth shading, edges and fine noise: every layer of the coder has work."""
    rng = np.random.default_rng(7)
    image = textured(h, w).astype(np.float64)
    image[h // 3: 2 * h // 3, w // 4: w // 2] += 40
    image += rng.normal(0, 6, image.shape)
    return np.clip(np.round(image), 0, 255).astype(np.uint8)


def test_quality_rises_with_bytes_and_the_size_is_hit():
    image = photo_like()
    curve = []
    for ratio in (3, 5, 8, 12, 20, 40):
        code = ifsforge.pifs_encode(image, ratio=ratio, threads=1)
        size = len(code.to_bytes())
        target = image.size // ratio
        assert 0.97 * target <= size <= target
        curve.append(psnr(image / 255.0, code.decode()))
    assert all(a > b for a, b in zip(curve, curve[1:])), curve
    assert curve[0] > 38  # the noise (sigma 6 levels, 32.5 dB) is coded too


def test_residual_beats_the_fractal_code_alone_at_low_ratios():
    image = photo_like()
    alone = ifsforge.pifs_encode(image, ratio=5, residual=False)
    hybrid = ifsforge.pifs_encode(image, ratio=5)
    assert alone.cost()["residual_bits"] == 0
    assert len(hybrid.to_bytes()) <= image.size // 5
    assert psnr(image / 255.0, hybrid.decode()) > psnr(image / 255.0, alone.decode()) + 1.5
    cost = hybrid.cost()
    parts = ("header", "quadtree", "contrast", "mean", "isometry", "domain", "residual")
    assert sum(cost[f"{p}_bits"] for p in parts) == pytest.approx(8 * cost["bytes"], rel=0.02)


def test_colour_residual_bytes_do_not_depend_on_threads():
    image = textured(70, 90, 3)
    one = ifsforge.pifs_encode(image, ratio=6, threads=1)
    two = ifsforge.pifs_encode(image, ratio=6, threads=2)
    assert one.to_bytes() == two.to_bytes()
    assert one.cost()["residual_bits"] > 0
    assert np.array_equal(one.decode(threads=1), two.decode(threads=2))


def test_residual_follows_the_zoom():
    # At 2x the native residual is interpolated: averaged back to 1x it is nearly the 1x image;
    # at 1/2 it is the 1x residual averaged.
    image = photo_like()
    code = ifsforge.pifs_encode(image, ratio=6)
    one = code.decode(deblock=False)
    two = code.decode(scale=2, deblock=False)
    assert psnr(one, two.reshape(96, 2, 128, 2).mean(axis=(1, 3))) > 35
    half = code.decode(scale=0.5, deblock=False)
    assert psnr(one.reshape(48, 2, 64, 2).mean(axis=(1, 3)), half) > 35


def test_version_one_file_still_decodes():
    # Written by the coder before the residual layer (textured(40, 48, 3) at 6:1).
    code = ifsforge.read_pifs(str(DATA / "pifs_version1.pifs"))
    out = code.decode()
    assert out.shape == (40, 48, 3)
    assert psnr(textured(40, 48, 3) / 255.0, out) > 28
    assert code.cost()["residual_bits"] == 0
    again = ifsforge.pifs_from_bytes(code.to_bytes())  # rewritten as the current version
    assert code.to_bytes()[4] == 2
    assert np.array_equal(again.decode(), out)


def test_cli_info_gives_a_version_one_files_own_size(cli):
    path = DATA / "pifs_version1.pifs"
    info = json.loads(cli("info", path, "--json", check=True).stdout)
    assert info["bytes"] == path.stat().st_size
    assert info["cost_bits"]["residual"] == 0


def test_cli_no_residual(cli, tmp_path):
    png = tmp_path / "in.png"
    ifsforge.write_png(str(png), photo_like())
    residual_bits = {}
    for flag in ([], ["--no-residual"]):
        out = tmp_path / f"out{len(flag)}.pifs"
        info = json.loads(cli("compress", png, "-o", out, "--ratio", "5", "--json", *flag, check=True).stdout)
        assert info["bytes"] == out.stat().st_size <= 96 * 128 // 5
        residual_bits[bool(flag)] = info["cost_bits"]["residual"]
    assert residual_bits[True] == 0 < residual_bits[False]
