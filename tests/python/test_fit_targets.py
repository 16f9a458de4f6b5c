"""fit on colour pictures (seed Fig. 4.3: one collage per channel) and 3D shapes (.vdb and meshes),
from Python and the CLI, with truths: targets drawn from known systems."""
import json

import numpy as np
import pytest

import ifsforge

from conftest import SAMPLES

# The Sierpinski sample's colour is a function of the position, so its colour maps have exact
# solutions: the error is near zero, and the bars leave room for the chaos game's noise.
COLOUR_ERROR_BAR = 0.01
COLOUR_COLLAGE_BAR = 0.01


def color_error(target, drawn):
    """Mean |colour difference| (over r, g, b) on the pixels both pictures cover, and their IoU."""
    t, d = ifsforge.color_foreground(target), drawn[..., :3].max(axis=2) > 0
    both = t & d
    return float(np.abs(target[..., :3] - drawn[..., :3])[both].mean()), float(both.sum() / (t | d).sum())


def test_fit_colors_a_colour_sierpinski(cli, tmp_path):
    cli("render", SAMPLES / "colour5d_sierpinski_rgb.json", "-o", "t.png", "--size", "128", check=True)
    summary = json.loads(cli("fit", "t.png", "-o", "fit.json", "--restarts", "2", "--seed", "1", "--json",
                             check=True).stdout)
    system = ifsforge.read_json(str(tmp_path / "fit.json"))
    assert system.layout == "xy+rgb" and summary["layout"] == "xy+rgb" and len(system) == 3
    assert set(summary["color_collage_error"]) == {"r", "g", "b"}
    assert max(summary["color_collage_error"].values()) < COLOUR_COLLAGE_BAR
    assert max(system.contraction_factors()) <= 0.9 + 1e-9  # colour maps contract too
    # `render` draws it (chaos game, colours by Eq. 101) like the target.
    cli("render", "fit.json", "-o", "fit.png", check=True)
    error, iou = color_error(ifsforge.read_png(str(tmp_path / "t.png")), ifsforge.read_png(str(tmp_path / "fit.png")))
    assert iou > 0.95 and error < COLOUR_ERROR_BAR, (iou, error)


def test_fit_color_follows_the_picture_not_the_shape_alone():
    # The same shape with the colours swapped round the copies: the rows follow the picture.
    system = ifsforge.load(str(SAMPLES / "colour5d_sierpinski_rgb.json"))
    picture = np.asarray(ifsforge.render(system, "mpa", 96, 96, window=[-0.03, -0.03, 1.03, 1.03]).to_image(), np.float32)
    shape = ifsforge.fit(ifsforge.color_foreground(picture), maps=3, restarts=1, seed=2)["system"]
    a = ifsforge.fit_color(shape, picture)
    b = ifsforge.fit_color(shape, np.ascontiguousarray(picture[..., ::-1]))  # r and b exchanged
    assert max(a["collage_error"]) < 0.02 and max(b["collage_error"]) < 0.02
    ra, rb = ifsforge.to_json(a["system"]), ifsforge.to_json(b["system"])
    assert ra != rb
    # Diagonal colour maps without a gradient fit worse: the sample's blue grows with height.
    plain = ifsforge.fit_color(shape, picture, positional=False, mixing=False)
    assert plain["collage_error"][2] > a["collage_error"][2]


def test_fit_color_refuses_bad_input(cli, tmp_path):
    shape = ifsforge.parse_json('{"format": "ifsforge/1", "name": "s", "layout": "xy", "maps": ['
                                '{"scale": 0.5, "translation": [0, 0]}, {"scale": 0.5, "translation": [0.5, 0.5]}]}')
    with pytest.raises(ifsforge.InputError, match="RGB"):
        ifsforge.fit_color(shape, np.zeros((8, 8), np.float32), np.ones((8, 8), bool))
    with pytest.raises(ifsforge.InputError, match="no shape"):
        ifsforge.color_foreground(np.zeros((8, 8, 3), np.float32))
    ifsforge.write_png(str(tmp_path / "flat.png"), np.full((16, 16, 3), (0.2, 0.4, 0.6), np.float32))
    result = cli("fit", "flat.png", "-o", "x.json")
    assert result.returncode != 0 and "flat.png" in result.stderr and "no shape" in result.stderr
    assert not (tmp_path / "x.json").exists()


def tetrahedron_mask(n=64):
    i = np.arange(n)
    x, y, z = np.meshgrid(i, i, i, indexing="ij")
    return ((x & y) == 0) & ((y & z) == 0) & ((x & z) == 0)


@pytest.mark.long
def test_fit_recovers_a_sierpinski_tetrahedron_from_a_vdb(cli, tmp_path):
    cli("volume", SAMPLES / "sierpinski_tetrahedron.json", "-o", "t.vdb", "--res", "64", check=True)
    target = ifsforge.read_voxel_target(str(tmp_path / "t.vdb"))
    assert target["mask"].shape == (64, 64, 64) and target["voxel_size"] == pytest.approx(1 / 64)
    assert (target["mask"] == tetrahedron_mask()).all()  # exactly its 4^6 cells
    # One CMA-ES run recovers it exactly (IoU 1.0, corners on the lattice); the default four cost 1.7
    # times more (tests/cpp Fit3d.RecoversATetrahedronAndIsIndependentOfThreads runs two).
    summary = json.loads(cli("fit", "t.vdb", "-o", "fit.json", "--threads", "2", "--restarts", "1", "--json",
                             check=True).stdout)
    assert summary["maps"] == 4 and summary["iou"] >= 0.8 and summary["bounds"] == pytest.approx([0, 0, 0, 1, 1, 1])
    system = ifsforge.read_json(str(tmp_path / "fit.json"))
    assert system.layout == "xyz" and max(system.contraction_factors()) <= 0.9 + 1e-9
    assert ifsforge.attractor_iou_3d(system, **target, seed=3) >= 0.8
    # `volume` frames it like the target: its own box is the target's, so the voxels agree.
    cli("volume", "fit.json", "-o", "fit.vdb", "--res", "64", check=True)
    drawn = ifsforge.read_voxel_target(str(tmp_path / "fit.vdb"))
    assert drawn["origin"] == pytest.approx(target["origin"], abs=0.02)
    assert drawn["mask"].shape == target["mask"].shape
    both = (drawn["mask"] & target["mask"]).sum() / (drawn["mask"] | target["mask"]).sum()
    assert both >= 0.8, both
    # The IoU printed is the one `volume` gives on the printed --bounds at the target's voxel count.
    boxed = ifsforge.render_volume(system, "prr", resolution=64, bounds=summary["bounds"])
    seen = np.zeros((64, 64, 64), bool)
    seen[tuple(np.asarray(boxed.coords).T)] = True
    assert boxed.dims == [64, 64, 64] or tuple(boxed.dims) == (64, 64, 64)
    assert summary["iou"] == pytest.approx((seen & target["mask"]).sum() / (seen | target["mask"]).sum(), abs=1e-12)


def test_fit_3d_is_identical_for_any_thread_count():
    mask = tetrahedron_mask(16)
    options = dict(maps=4, raster=8, refine_raster=16, restarts=1, generations=20, attractor_generations=5,
                   final_generations=10, seed=4)
    runs = [ifsforge.fit_3d(mask, (0, 0, 0), 1 / 16, threads=t, **options) for t in (1, 2)]
    assert ifsforge.to_json(runs[0]["system"]) == ifsforge.to_json(runs[1]["system"])


def cube_obj(path, lo=-1.0, hi=1.0):
    corners = [(x, y, z) for x in (lo, hi) for y in (lo, hi) for z in (lo, hi)]
    faces = [(1, 3, 4, 2), (5, 6, 8, 7), (1, 2, 6, 5), (3, 7, 8, 4), (1, 5, 7, 3), (2, 4, 8, 6)]
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in corners) + "".join(
        "f " + " ".join(map(str, f)) + "\n" for f in faces))


@pytest.mark.long
def test_a_mesh_is_voxelised_inside(tmp_path):
    # A flat triangle is a sheet one voxel thick (its surface passes within half a voxel).
    (tmp_path / "flat.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    sheet = ifsforge.read_voxel_target(str(tmp_path / "flat.obj"))
    assert sheet["mask"].shape == (64, 64, 1) and 0.45 < sheet["mask"].mean() < 0.55
    cube_obj(tmp_path / "cube.obj")
    target = ifsforge.read_voxel_target(str(tmp_path / "cube.obj"), resolution=16)
    assert target["mask"].shape == (16, 16, 16) and target["mask"].all()
    assert target["origin"] == pytest.approx((-1, -1, -1)) and target["voxel_size"] == pytest.approx(2 / 16)
    # The cube is the attractor of its 8 half copies: the fit finds a tiling (IoU 1.0 within 100
    # generations of the last search; the default 300 took 13 of the test's 21 CPU seconds more).
    result = ifsforge.fit_3d(**target, maps=8, raster=8, refine_raster=16, restarts=1, final_generations=100, seed=1,
                             threads=2)
    assert result["iou"] > 0.9


def test_bad_3d_targets_are_input_errors(cli, tmp_path):
    (tmp_path / "junk.vdb").write_bytes(b"not a vdb at all" * 8)
    (tmp_path / "line.obj").write_text("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n")  # no area
    (tmp_path / "point.obj").write_text("v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n")
    for name, fragment in (("junk.vdb", "OpenVDB"), ("line.obj", "encloses no voxel"), ("point.obj", "no volume"),
                           ("t.xyz", "3D target")):
        if name == "t.xyz":
            (tmp_path / name).write_text("1 2 3")
        with pytest.raises(ifsforge.InputError, match=fragment):
            ifsforge.read_voxel_target(str(tmp_path / name))
    for name in ("junk.vdb", "line.obj"):
        result = cli("fit", name, "-o", "x.json")
        assert result.returncode != 0 and name in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "x.json").exists()
    with pytest.raises(ifsforge.InputError, match="no voxels"):
        ifsforge.fit_3d(np.zeros((4, 4, 4), bool))
    with pytest.raises(ifsforge.InputError, match="nx, ny, nz"):
        ifsforge.fit_3d(np.zeros((4, 4), bool))
    with pytest.raises(ifsforge.FileError):
        ifsforge.read_voxel_target(str(tmp_path / "missing.vdb"))


def test_collage_target_equals_collage_distance():
    picture = np.zeros((40, 40), np.float32)
    picture[8:32, 6:30] = 1
    prepared = ifsforge.CollageTarget(picture)
    system = ifsforge.load(str(SAMPLES / "sierpinski_triangle.json"))
    for window in ([0, 0, 1, 1], [-0.2, 0, 1.2, 1.1]):
        assert prepared.distance(system, window=window) == ifsforge.collage_distance(system, picture, window=window)
    assert prepared.mask.sum() == 24 * 24
