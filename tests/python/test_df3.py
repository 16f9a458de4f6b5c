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


def march(volume, density, view, size=96):
    """An independent emission-absorption render of the volume as the --pov scene's media define
    it (absorption density x value, emission that times the voxel's linear colour), orthographic
    from `view` (a direction from the volume towards the eye): per line of sight (opacity, emitted
    linear RGB)."""
    h, dims = volume.voxel_size, np.asarray(volume.dims)
    lo = np.asarray(volume.origin, np.float64)
    sigma, colors = np.zeros(tuple(dims)), np.zeros((*dims, 3))
    ijk = tuple(np.asarray(volume.coords).T)
    sigma[ijk] = density * np.asarray(volume.density, np.float64)
    colors[ijk] = srgb_to_linear(np.asarray(volume.attributes()["color"], np.float64)[:, :3])
    d = np.asarray(view, np.float64) / np.linalg.norm(view)
    u = np.cross(d, (0.0, 0.0, 1.0))
    u /= np.linalg.norm(u)
    v = np.cross(u, d)
    centre, radius = lo + dims * h / 2, np.linalg.norm(dims * h) / 2
    grid = np.linspace(-radius, radius, size)
    points = centre + grid[:, None, None] * u + grid[None, :, None] * v + radius * d  # (size, size, 3)
    step = h / 4
    transmittance, emitted = np.ones((size, size)), np.zeros((size, size, 3))
    for _ in range(int(2 * radius / step)):
        points = points - step * d
        index = np.floor((points - lo) / h).astype(int)
        inside = np.all((index >= 0) & (index < dims), axis=2)
        index[~inside] = 0
        s = np.where(inside, sigma[index[..., 0], index[..., 1], index[..., 2]], 0.0)
        absorbed = transmittance * -np.expm1(-s * step)
        emitted += absorbed[..., None] * colors[index[..., 0], index[..., 1], index[..., 2]]
        transmittance -= absorbed
    return 1.0 - transmittance, emitted


def test_volume_command_writes_the_colour_and_povray_renders_it(tmp_path, samples):
    """A colour volume's --df3 gets its linear red, green and blue beside it (write_df3's
    content), and the --pov scene's media show those colours in the real POV-Ray. Rendered on a
    black and on a white background, each pixel gives the medium's opacity (their difference) and
    its own colour (black's / opacity); where it is mostly opaque, its mean is the mean colour
    an independent emission-absorption march of the same voxels shows (CIEDE2000 <= 10)."""
    skimage_color = pytest.importorskip("skimage.color")
    from PIL import Image
    from ifsforge import media
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
    marched_opacity, emitted = march(volume, media.DENSITY * media.per_world_unit(volume), (1.0, -1.0, 0.8))
    solid = marched_opacity > 0.5
    expected = (emitted[solid] / marched_opacity[solid][:, None]).mean(axis=0)
    lab = [skimage_color.rgb2lab(linear_to_srgb(np.clip(c, 0, 1)).reshape(1, 1, 3)) for c in (seen, expected)]
    delta = float(skimage_color.deltaE_ciede2000(*lab)[0, 0])
    chroma = np.hypot(lab[0][0, 0, 1], lab[0][0, 0, 2])
    print(f"POV-Ray volume colour {linear_to_srgb(seen)} against the march's {linear_to_srgb(expected)}: "
          f"CIEDE2000 {delta:.1f}, chroma {chroma:.0f}")
    assert chroma > 10  # coloured, not the gray of a density-only medium
    assert delta <= 10, (seen, expected, delta)
