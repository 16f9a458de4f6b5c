"""ifsforge.write_df3 and `ifsforge volume --df3`: POV-Ray's density file read back byte by byte
(header, big-endian voxels, x fastest), every bit depth, bad input, and the real POV-Ray
rendering media from it."""
import subprocess
import sys

import numpy as np
import pytest

import ifsforge


@pytest.fixture
def volume(samples):
    system = ifsforge.load(str(samples / "sierpinski_tetrahedron.json"))
    return ifsforge.render_volume(system, "chaos", 12, density="hits", seed=3)


@pytest.mark.parametrize("bits, dtype", [(8, ">u1"), (16, ">u2"), (32, ">u4")])
def test_df3_holds_the_scaled_density(tmp_path, volume, bits, dtype):
    path = tmp_path / "v.df3"
    ifsforge.write_df3(str(path), volume, bits=bits)
    raw = path.read_bytes()
    nx, ny, nz = np.frombuffer(raw[:6], ">u2")
    assert [nx, ny, nz] == list(volume.dims)
    data = np.frombuffer(raw[6:], dtype)
    assert data.size == nx * ny * nz
    grid = data.reshape(nz, ny, nx).transpose(2, 1, 0)  # back to (x, y, z)
    dense = volume.to_dense("density").astype(np.float64)
    full = 2 ** bits - 1
    np.testing.assert_array_equal(grid, np.rint(dense / dense.max() * full).astype(np.uint64))
    assert grid.max() == full and (grid > 0).sum() == np.count_nonzero(np.rint(dense / dense.max() * full))


def test_df3_bad_input_names_the_file(tmp_path, volume):
    with pytest.raises(ifsforge.InputError, match="bits"):
        ifsforge.write_df3(str(tmp_path / "v.df3"), volume, bits=12)
    assert not (tmp_path / "v.df3").exists()
    with pytest.raises(ifsforge.FileError, match="missing"):
        ifsforge.write_df3(str(tmp_path / "missing" / "v.df3"), volume)


def test_povray_renders_media_from_the_df3(tmp_path, volume):
    ifsforge.write_df3(str(tmp_path / "v.df3"), volume)
    (tmp_path / "v.pov").write_text(
        '#version 3.7;\nglobal_settings { assumed_gamma 1.0 }\nbackground { rgb 1 }\n'
        'camera { location <0.5, 0.5, -2> look_at <0.5, 0.5, 0.5> right x up y angle 40 }\n'
        'box { 0, 1 pigment { rgbt 1 } hollow interior { media { absorption 40 density { density_file df3 "v.df3" '
        'interpolate 0 } } } }\n')
    subprocess.run(["povray", "+Iv.pov", "+Ov.png", "+W48", "+H48", "-D", "-V", "+FN"], cwd=tmp_path, check=True,
                   capture_output=True)
    from PIL import Image
    pixels = np.asarray(Image.open(tmp_path / "v.png").convert("L"), float) / 255
    # Dark where the tetrahedron absorbs, the white background elsewhere.
    assert (pixels < 0.5).mean() > 0.05 and (pixels > 0.95).mean() > 0.3


def test_volume_command_writes_the_df3(tmp_path, samples):
    out = tmp_path / "t.df3"
    subprocess.run([sys.executable, "-m", "ifsforge", "volume", str(samples / "sierpinski_tetrahedron.json"),
                    "--res", "16", "--df3", str(out), "--df3-bits", "16"], check=True, capture_output=True)
    system = ifsforge.load(str(samples / "sierpinski_tetrahedron.json"))
    volume = ifsforge.render_volume(system, "prr", 16)
    ifsforge.write_df3(str(tmp_path / "same.df3"), volume, bits=16)
    assert out.read_bytes() == (tmp_path / "same.df3").read_bytes()
    bad = subprocess.run([sys.executable, "-m", "ifsforge", "volume", str(samples / "sierpinski_tetrahedron.json"),
                          "--df3", str(tmp_path / "t.vdb")], capture_output=True, text=True)
    assert bad.returncode != 0 and "--df3 expects a .df3 file" in bad.stderr


def srgb_to_linear(values):
    return np.where(values <= 0.04045, values / 12.92, ((values + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(values):
    return np.where(values <= 0.0031308, 12.92 * values, 1.055 * values ** (1 / 2.4) - 0.055)


def test_volume_command_writes_the_colour_and_povray_renders_it(tmp_path, samples):
    """A colour volume's --df3 gets its linear red, green and blue beside it (write_df3's
    content), and the --pov scene's media show those colours in the real POV-Ray. Rendered on a
    black and on a white background, each pixel gives the medium's opacity (their difference) and
    its own colour (black's / opacity); where it is mostly opaque, that colour has the hue of the
    voxels' mean display colour (the outer voxels, which the eye sees, are not all of them, so
    the hue, not the whole colour, is what must agree)."""
    skimage_color = pytest.importorskip("skimage.color")
    from PIL import Image
    source = samples / "volume_sierpinski_pyramid_rgb.json"
    subprocess.run([sys.executable, "-m", "ifsforge", "volume", str(source), "--res", "24", "--df3", str(tmp_path / "c.df3"),
                    "--df3-bits", "16", "--pov", str(tmp_path / "c.pov"), "--pov-size", "96x96"],
                   check=True, capture_output=True)
    volume = ifsforge.render_volume(ifsforge.load(str(source)), "prr", 24)
    for content in ("density", "red", "green", "blue"):
        name = "c.df3" if content == "density" else f"c_{content}.df3"
        ifsforge.write_df3(str(tmp_path / f"same_{name}"), volume, bits=16, content=content)
        assert (tmp_path / name).read_bytes() == (tmp_path / f"same_{name}").read_bytes(), name
    text = (tmp_path / "c.pov").read_text()
    assert all(f'"c_{c}.df3"' in text for c in ("red", "green", "blue")) and "background { rgb 0 }" in text
    (tmp_path / "w.pov").write_text(text.replace("background { rgb 0 }", "background { rgb 1 }"))
    images = []
    for stem in ("c", "w"):
        run = subprocess.run(["povray", f"+I{stem}.pov", f"+O{stem}.png", "+W96", "+H96", "-D", "-V", "+FN", "+A0.1"],
                             cwd=tmp_path, capture_output=True, text=True)
        assert run.returncode == 0 and "not perpendicular" not in run.stderr, run.stderr[-2000:]
        images.append(srgb_to_linear(np.asarray(Image.open(tmp_path / f"{stem}.png").convert("RGB"), np.float64) / 255))
    black, white = images
    opacity = 1.0 - (white - black).mean(axis=2)
    opaque = opacity > 0.5
    assert opaque.mean() > 0.05, opaque.mean()
    seen = (black[opaque] / opacity[opaque][:, None]).mean(axis=0)
    expected = srgb_to_linear(np.asarray(volume.attributes()["color"], np.float64)[:, :3]).mean(axis=0)
    lab = [skimage_color.rgb2lab(linear_to_srgb(np.clip(c, 0, 1)).reshape(1, 1, 3)) for c in (seen, expected)]
    hue = [np.degrees(np.arctan2(c[0, 0, 2], c[0, 0, 1])) for c in lab]
    chroma = [np.hypot(c[0, 0, 1], c[0, 0, 2]) for c in lab]
    assert chroma[1] > 10 and chroma[0] > 10, chroma  # coloured, not the gray of a density-only medium
    print(f"POV-Ray volume colour {linear_to_srgb(seen)} against the voxels' {linear_to_srgb(expected)}: "
          f"CIEDE2000 {float(skimage_color.deltaE_ciede2000(*lab)[0, 0]):.1f}, hue {hue[0]:.0f} vs {hue[1]:.0f} degrees")
    assert abs(hue[0] - hue[1]) <= 20, (seen, expected, hue)
