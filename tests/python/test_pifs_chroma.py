"""PIFS colour at rich budgets: full-size (4:4:4) chroma where averaging the chroma 2×2 would cap
the quality, chosen by default under a size target, reached from Python and the CLI."""
import json

import numpy as np
import pytest

import ifsforge


def psnr(a, b):
    return 10 * np.log10(1.0 / np.mean((np.asarray(a, np.float64) - b) ** 2))


def fine_chroma(h=96, w=128):
    """Hue that changes every pixel, as in printed text or thin coloured lines: what 4:2:0 loses."""
    y, x = np.mgrid[0:h, 0:w]
    image = np.zeros((h, w, 3))
    image[..., 0] = 0.5 + 0.4 * ((x + y) % 2)
    image[..., 1] = 0.45 + 0.1 * np.sin(x / 9.0)
    image[..., 2] = 0.9 - 0.4 * ((x + y) % 2)
    return np.round(image * 255).astype(np.uint8)


def smooth_colour(h=96, w=128):
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    image = np.stack([0.5 + 0.3 * np.sin(x / 17 + c) * np.cos(y / 23) + 0.1 * np.sin((x + 2 * y) / 5 + c)
                      for c in range(3)], axis=-1)
    return np.round(np.clip(image, 0, 1) * 255).astype(np.uint8)


def test_full_chroma_codes_every_plane_at_full_size_and_round_trips():
    image = fine_chroma()
    code = ifsforge.pifs_encode(image, ratio=5, chroma="full")
    assert code.color == "ycbcr444"
    assert code.plane_sizes == [(128, 96)] * 3
    again = ifsforge.pifs_from_bytes(code.to_bytes())
    assert again.to_bytes() == code.to_bytes() and again.color == "ycbcr444"
    assert np.array_equal(again.decode(), code.decode())
    assert code.decode(scale=2).shape == (192, 256, 3)
    assert ifsforge.choices["chroma"] == ["auto", "half", "full"]


def test_automatic_chroma_is_full_where_half_caps_the_quality():
    image = fine_chroma()
    half = ifsforge.pifs_encode(image, ratio=5, chroma="half")
    full = ifsforge.pifs_encode(image, ratio=5, chroma="full")
    auto = ifsforge.pifs_encode(image, ratio=5)
    assert half.color == "ycbcr420"
    # Half-size chroma cannot follow a hue that alternates every pixel, whatever the bytes.
    assert psnr(image / 255.0, full.decode()) > psnr(image / 255.0, half.decode()) + 6
    assert auto.to_bytes() == full.to_bytes()
    assert ifsforge.pifs_encode(image, ratio=5, threads=1).to_bytes() == ifsforge.pifs_encode(
        image, ratio=5, threads=2).to_bytes()


@pytest.mark.parametrize("rate", [dict(ratio=100), dict(quality=8)])
def test_automatic_chroma_stays_half_where_it_costs_nothing(rate):
    # Smooth colour at a tight budget, or no size target at all: the seed's 4:2:0 (Step 2).
    image = smooth_colour()
    auto = ifsforge.pifs_encode(image, **rate)
    assert auto.color == "ycbcr420"
    assert auto.to_bytes() == ifsforge.pifs_encode(image, chroma="half", **rate).to_bytes()


def test_cli_chroma_option(cli, tmp_path):
    source = tmp_path / "lines.png"
    ifsforge.write_png(str(source), fine_chroma())
    for chroma, expected in [("auto", "ycbcr444"), ("half", "ycbcr420"), ("full", "ycbcr444")]:
        out = tmp_path / f"{chroma}.pifs"
        cli("compress", source, "-o", out, "--ratio", "5", "--chroma", chroma, check=True)
        assert json.loads(cli("info", out, "--json", check=True).stdout)["color"] == expected
    png = tmp_path / "back.png"
    cli("decompress", tmp_path / "auto.pifs", "-o", png, check=True)
    assert psnr(fine_chroma() / 255.0, ifsforge.read_png(str(png))) > 35
    bad = cli("compress", source, "-o", tmp_path / "x.pifs", "--chroma", "quarter")
    assert bad.returncode == 2 and "--chroma" in bad.stderr and not (tmp_path / "x.pifs").exists()
