"""The add-on's POV-Ray export renders as Cycles does: one scene of coloured instances, a terrain,
a coloured iso-surface and a colour volume under a sun and a coloured world, rendered by both
(tests/blender/povray_vs_cycles.py). Each object rendered alone covers the same pixels in both
(silhouette IoU >= 0.9: placement, camera, density scale), and in the whole scene each object's
region has the same mean colour (CIEDE2000 <= 10: per-instance colours, sRGB vertex colours,
the colour volume, light units, the world as background and ambient light)."""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from test_blender_addon import run_blender

skimage_color = pytest.importorskip("skimage.color")
# long: the renders below, one Blender and one POV-Ray run that every test shares.
pytestmark = [pytest.mark.skipif(not shutil.which("blender") or not shutil.which("povray"),
                                 reason="needs Blender and POV-Ray"), pytest.mark.long]

MAX_DELTA_E = 10.0
MIN_IOU = 0.9
BACKGROUND_STEP = 0.06  # sRGB: a pixel this far from the world's colour shows an object


def load(path):
    return np.asarray(Image.open(path).convert("RGB"), np.float64) / 255.0


def silhouette(image, background):
    return np.abs(image - background).max(axis=2) > BACKGROUND_STEP


def iou(a, b):
    return (a & b).sum() / max((a | b).sum(), 1)


def srgb(linear):
    linear = np.asarray(linear, np.float64)
    return np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1 / 2.4) - 0.055)


def mean_delta_e(a, b, region):
    """CIEDE2000 between the mean sRGB colours of two images over `region`."""
    lab = [skimage_color.rgb2lab(image[region].mean(axis=0).reshape(1, 1, 3)) for image in (a, b)]
    return float(skimage_color.deltaE_ciede2000(*lab)[0, 0])


@pytest.fixture(scope="module")
def renders(tmp_path_factory):
    report = run_blender("povray_vs_cycles.py", tmp_path_factory.mktemp("povray_vs_cycles"), timeout=600)
    images = {name: [load(p) for p in paths] for name, paths in report["values"]["images"].items()}
    return images, srgb(report["values"]["world"]), Path(report["values"]["images"]["all"][1]).with_suffix(".pov")


def test_the_camera_vectors_are_perpendicular(renders):
    scene = renders[2]
    result = subprocess.run(["povray", f"+I{scene.name}", "+Ocheck.png", "+W16", "+H12", "-D", "-A"],
                            cwd=scene.parent, capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "perpendicular" not in result.stdout + result.stderr


def test_the_world_is_the_background(renders):
    images, background, _ = renders
    cycles, povray = images["all"]
    corner = np.s_[:6, :6]  # sky in both
    np.testing.assert_allclose(cycles[corner].mean(axis=(0, 1)), background, atol=2 / 255)
    np.testing.assert_allclose(povray[corner].mean(axis=(0, 1)), background, atol=2 / 255)


def test_each_object_covers_the_same_pixels(renders):
    images, background, _ = renders
    for name in ("instances", "terrain", "isosurface", "volume"):
        cycles, povray = (silhouette(image, background) for image in images[name])
        assert 0.01 < cycles.mean() < 0.5, (name, cycles.mean())
        overlap = iou(cycles, povray)
        print(f"{name}: silhouette IoU {overlap:.3f}")
        assert overlap >= MIN_IOU, (name, overlap)


def test_each_object_has_the_same_mean_color(renders):
    images, background, _ = renders
    masks = {name: silhouette(images[name][0], background)
             for name in ("instances", "terrain", "isosurface", "volume")}
    cycles, povray = images["all"]
    for name, mask in masks.items():
        region = mask & ~np.any([m for other, m in masks.items() if other != name], axis=0)
        assert region.sum() > 50, (name, region.sum())
        difference = mean_delta_e(cycles, povray, region)
        print(f"{name}: mean colour Cycles {np.round(cycles[region].mean(axis=0) * 255)} "
              f"POV-Ray {np.round(povray[region].mean(axis=0) * 255)}, CIEDE2000 {difference:.2f}")
        assert difference <= MAX_DELTA_E, (name, difference)
