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
