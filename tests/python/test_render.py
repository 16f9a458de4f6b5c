"""Rendering through Python: determinism, colour stealing, progress, PNG round trip."""
import math

import numpy as np
import pytest

import ifsforge

HALF = [[0.5, 0], [0, 0.5]]


@pytest.fixture
def sierpinski():
    return ifsforge.Ifs([ifsforge.AffineMap(HALF, o) for o in ([0, 0], [0.5, 0], [0.25, 0.5])], name="s")


@pytest.mark.parametrize("algorithm", ["chaos", "prr"])
def test_identical_for_any_thread_count(sierpinski, algorithm):
    one = ifsforge.render(sierpinski, algorithm, 200, iterations=2_000_000, seed=5, threads=1)
    two = ifsforge.render(sierpinski, algorithm, 200, iterations=2_000_000, seed=5, threads=2)
    np.testing.assert_array_equal(one.density, two.density)
    assert one.covered() > 1000


def test_color_stealing_takes_the_reference_colors(sierpinski):
    # A reference picture split in a red left half and a blue right half: with the default
    # grid reference system, map 0 walks the left column and maps 1, 2 the right one.
    picture = np.zeros((64, 64, 3), np.float32)
    picture[:, :32, 0] = 1.0
    picture[:, 32:, 2] = 1.0
    r1 = ifsforge.render(sierpinski, "color-stealing", 128, reference_image=picture, threads=1, seed=3)
    r2 = ifsforge.render(sierpinski, "color-stealing", 128, reference_image=picture, threads=2, seed=3)
    np.testing.assert_array_equal(r1.channels, r2.channels)
    image = r1.to_image("color")
    assert image.shape == (128, 128, 3)
    covered = r1.mask
    # Every covered pixel is a mix of red and blue only.
    assert np.all(image[covered][:, 1] == 0)
    assert image[covered][:, 0].max() > 0.9 and image[covered][:, 2].max() > 0.9


def test_progress_is_reported_and_cancels(sierpinski):
    seen = []
    ifsforge.render(sierpinski, "chaos", 64, iterations=20_000_000, progress=lambda f: seen.append(f))
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(ifsforge.Cancelled):
        ifsforge.render(sierpinski, "chaos", 64, iterations=50_000_000, progress=lambda f: False)


def test_png_round_trip(tmp_path):
    image = np.linspace(0, 1, 4 * 6 * 3, dtype=np.float32).reshape(4, 6, 3)
    for bits, step in ((8, 1 / 255), (16, 1 / 65535)):
        path = tmp_path / f"x{bits}.png"
        ifsforge.write_png(str(path), image, bits)
        np.testing.assert_allclose(ifsforge.read_png(str(path)), image, atol=step * 0.51)
    with pytest.raises(ifsforge.FileError):
        ifsforge.write_png(str(tmp_path / "missing" / "x.png"), image)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x16.png", "x8.png"]


def test_density_image_is_log_scaled(sierpinski):
    raster = ifsforge.render(sierpinski, "prr", 64, depth=6)
    image = raster.to_image("density")
    assert image.max() == pytest.approx(1.0)
    assert np.all((image > 0) == raster.mask)
    assert raster.density.sum() == pytest.approx(1.0, abs=1e-5)


def test_prr_falls_back_to_a_fixed_depth_when_pieces_never_fit_a_pixel():
    # A fractal interpolation graph with vertical factors 0.97: pieces thin to 1/5^k wide but
    # stay tall; the pixel-size stop would split for ever. PRR renders at the fixed depth whose
    # 5^L leaves match Eq. 45's coverage count (H V ln(mu H V)), at least Eq. 59's.
    maps = [ifsforge.AffineMap([[0.2, 0], [0.1 * (i % 2) - 0.05, 0.97]], [0.2 * i, 0.05 * (i % 2)]) for i in range(5)]
    rough = ifsforge.Ifs(maps, name="rough")
    fallback = ifsforge.render(rough, "prr", 256)
    pixels = 256 * 256
    depth = math.ceil(math.log(pixels * math.log(1.78107 * pixels)) / math.log(5))
    assert depth == 9 and depth > ifsforge.default_depth(5, 256, 256)
    fixed = ifsforge.render(rough, "prr", 256, depth=depth)
    np.testing.assert_array_equal(fallback.density, fixed.density)
    assert fallback.points == 5 ** 9
    assert ifsforge.render(rough, "chaos", 256, binary=True).covered() > 256
