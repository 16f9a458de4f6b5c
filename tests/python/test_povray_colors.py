"""Colours in POV-Ray files: a colour volume's .df3 channels hold the linear colour (what media
coefficients multiply), with an optional empty border; instance scenes write every display
colour as srgb and frame cameras POV-Ray finds perpendicular."""
import re
import shutil
import subprocess

import numpy as np
import pytest

import ifsforge
from conftest import SAMPLES


def read_df3(path, dtype=">u2"):
    raw = path.read_bytes()
    nx, ny, nz = np.frombuffer(raw[:6], ">u2")
    return np.frombuffer(raw[6:], dtype).reshape(nz, ny, nx).transpose(2, 1, 0)  # back to (x, y, z)


@pytest.fixture(scope="module")
def volume():
    system = ifsforge.load(str(SAMPLES / "volume_sierpinski_pyramid_rgb.json"))
    return ifsforge.render_volume(system, "prr", 16)


def test_color_channels_are_linear(tmp_path, volume):
    coords = np.asarray(volume.coords)
    linear = ifsforge.srgb_to_linear(np.asarray(volume.color, np.float64))
    for k, channel in enumerate(("red", "green", "blue")):
        path = tmp_path / f"{channel}.df3"
        ifsforge.write_df3(str(path), volume, bits=16, content=channel)
        grid = read_df3(path)
        assert list(grid.shape) == list(volume.dims)
        values = grid[coords[:, 0], coords[:, 1], coords[:, 2]] / 65535.0
        np.testing.assert_allclose(values, linear[:, k], atol=0.5 / 65535 + 1e-6)
        assert np.count_nonzero(grid) == np.count_nonzero(values)  # empty voxels stay 0


def test_a_border_surrounds_the_grid(tmp_path, volume):
    ifsforge.write_df3(str(tmp_path / "plain.df3"), volume, bits=8)
    ifsforge.write_df3(str(tmp_path / "border.df3"), volume, bits=8, border=True)
    plain, bordered = read_df3(tmp_path / "plain.df3", ">u1"), read_df3(tmp_path / "border.df3", ">u1")
    assert [n + 2 for n in plain.shape] == list(bordered.shape)
    np.testing.assert_array_equal(bordered[1:-1, 1:-1, 1:-1], plain)
    assert bordered.sum(dtype=np.int64) == plain.sum(dtype=np.int64)  # nothing but zeros around


def test_a_volume_without_color_has_no_color_channel(tmp_path, samples):
    volume = ifsforge.render_volume(ifsforge.load(str(samples / "sierpinski_tetrahedron.json")), "prr", 8)
    with pytest.raises(ifsforge.InputError, match="no colou?r"):
        ifsforge.write_df3(str(tmp_path / "r.df3"), volume, content="red")
    with pytest.raises(ifsforge.InputError, match="df3 content"):
        ifsforge.write_df3(str(tmp_path / "r.df3"), volume, content="alpha")
    assert not (tmp_path / "r.df3").exists()


@pytest.mark.skipif(not shutil.which("povray"), reason="needs POV-Ray")
@pytest.mark.parametrize("view, orthographic", [((30, 25), False), ((120, -40), False), ((0, 90), True)])
def test_instance_scenes_are_srgb_and_their_cameras_perpendicular(tmp_path, samples, view, orthographic):
    instances = ifsforge.instances(ifsforge.load(str(samples / "menger_sponge.json")), depth=2)
    scene = tmp_path / "s.pov"
    ifsforge.write_pov_scene(str(scene), instances, width=40, height=30, view=view, orthographic=orthographic,
                             sky=False, background=[0.5, 0.25, 0.125])
    text = scene.read_text()
    assert len(re.findall(r"pigment\{srgb<", text)) == len(instances) and " rgb <" not in text
    assert "background { srgb <0.5,0.25,0.125> }" in text
    result = subprocess.run(["povray", "+Is.pov", "+Os.png", "+W40", "+H30", "-D", "-A"], cwd=tmp_path,
                            capture_output=True, text=True)
    assert result.returncode == 0, result.stderr[-2000:]
    assert "perpendicular" not in result.stderr + result.stdout
