"""The volume binding and the `ifsforge volume` command: numpy arrays, OpenVDB files read back by
python3-openvdb (an independent reader), meshes, progress, bad input; and Blender importing the
.vdb as a Volume object (skipped only when Blender is absent)."""
import json
import subprocess
from pathlib import Path

import numpy as np
import pyopenvdb
import pytest

import ifsforge

ROOT = Path(__file__).resolve().parents[2]


def constant_color_tetrahedron(rgb):
    """The Sierpinski tetrahedron whose maps all set the colour `rgb`."""
    rows = [[0, 0, 0, 0, 0, 0, c] for c in rgb]
    maps = [{"scale": [0.5] * 3, "rotation": [0, 0, 0], "translation": t, "channels": rows}
            for t in ([0, 0, 0], [0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5])]
    return ifsforge.parse_json(json.dumps({"format": "ifsforge/1", "name": "tinted", "layout": "xyz+rgb",
                                           "probabilities": "uniform", "maps": maps}))


def test_volume_arrays_describe_the_exact_tetrahedron(samples):
    tetra = ifsforge.load(str(samples / "sierpinski_tetrahedron.json"))
    volume = ifsforge.render_volume(tetra, "prr", 32, bounds=(0, 0, 0, 1, 1, 1), depth=5)
    assert len(volume) == 4 ** 5
    coords = volume.coords
    assert coords.shape == (1024, 3) and coords.dtype == np.int32
    # Cell (i, j, k) of level 5 is filled iff i, j and k share no binary digit.
    assert not np.any(coords[:, 0] & coords[:, 1]) and not np.any(coords[:, 1] & coords[:, 2])
    assert np.allclose(volume.positions, np.asarray(volume.origin) + (coords + 0.5) * volume.voxel_size)
    assert volume.dims == [32, 32, 32] and volume.voxel_size == pytest.approx(1 / 32)
    assert np.all(volume.density == 1.0) and volume.density_mode == "binary"
    dense = volume.to_dense("occupancy")
    assert dense.shape == (32, 32, 32) and dense.sum() == 1024


def test_vdb_half_and_compression_make_smaller_files(tmp_path, samples):
    system = ifsforge.load(str(samples / "volume_sierpinski_pyramid_rgb.json"))
    volume = ifsforge.render_volume(system, "prr", 64)
    sizes = {}
    for half in (False, True):
        for compress in (False, True):
            path = tmp_path / f"{half}{compress}.vdb"
            ifsforge.write_vdb(str(path), volume, half=half, compress=compress)
            sizes[half, compress] = path.stat().st_size
    # Colour is 3/4 of the payload: halves save at least a third; Blosc saves more on top.
    assert sizes[True, False] < 0.67 * sizes[False, False]
    assert sizes[True, True] < sizes[True, False] and sizes[False, True] < sizes[False, False]


@pytest.mark.parametrize("half, compress, tolerance", [(True, False, 2.0 ** -11), (False, False, 1e-6),
                                                      (True, True, 2.0 ** -11), (False, True, 1e-6)])
def test_vdb_read_back_by_pyopenvdb(tmp_path, samples, half, compress, tolerance):
    system = ifsforge.load(str(samples / "volume_sierpinski_pyramid_rgb.json"))
    volume = ifsforge.render_volume(system, "prr", 48)
    path = tmp_path / "pyramid.vdb"
    ifsforge.write_vdb(str(path), volume, system=system, half=half, compress=compress)
    grids, meta = pyopenvdb.readAll(str(path))
    assert {g.name for g in grids} == {"density", "color"}
    for grid in grids:
        assert grid.activeVoxelCount() == len(volume)
    density = pyopenvdb.read(str(path), "density")
    color = pyopenvdb.read(str(path), "color")
    assert density.gridClass == "fog volume"
    # The transform puts voxel (i, j, k) where the system puts it, and every value matches, to
    # half precision (relative 2^-11) or to float rounding; the colour grid holds the display
    # colours decoded to linear (what Blender's Principled Volume reads) in float arithmetic.
    accessor, density_accessor = color.getConstAccessor(), density.getConstAccessor()
    colors = ifsforge.srgb_to_linear(volume.color)
    for index in range(len(volume)):
        ijk = tuple(int(c) for c in volume.coords[index])
        assert np.allclose(accessor.getValue(ijk), colors[index], rtol=tolerance, atol=0)
        assert density_accessor.getValue(ijk) == 1.0
    for index in (0, len(volume) // 2, len(volume) - 1):
        ijk = tuple(int(c) for c in volume.coords[index])
        assert np.allclose(density.transform.indexToWorld(ijk), volume.positions[index])
    assert ifsforge.parse_json(meta["ifsforge_system"]).name == system.name
    assert meta["ifsforge_algorithm"] == "prr" and meta["ifsforge_layout"] == "xyz+rgb"


def test_vdb_translation_moves_every_grid(tmp_path, samples):
    """translation is added to the transform of every grid (what centres a Blender volume on its
    origin), is recorded in the metadata, and leaves the voxels and their values alone."""
    system = ifsforge.load(str(samples / "volume_sierpinski_pyramid_rgb.json"))
    volume = ifsforge.render_volume(system, "prr", 16)
    lo, hi = np.asarray(volume.bounds[:3]), np.asarray(volume.bounds[3:])
    shift = -(lo + hi) / 2
    plain, moved = tmp_path / "plain.vdb", tmp_path / "moved.vdb"
    ifsforge.write_vdb(str(plain), volume, system=system)
    ifsforge.write_vdb(str(moved), volume, system=system, translation=list(shift))
    for name in ("density", "color"):
        a, b = pyopenvdb.read(str(plain), name), pyopenvdb.read(str(moved), name)
        assert a.activeVoxelCount() == b.activeVoxelCount() == len(volume)
        for index in (0, len(volume) - 1):
            ijk = tuple(int(c) for c in volume.coords[index])
            assert np.allclose(b.transform.indexToWorld(ijk), np.asarray(volume.positions[index]) + shift, atol=1e-12)
            assert a.getConstAccessor().getValue(ijk) == b.getConstAccessor().getValue(ijk)
    meta = pyopenvdb.readAll(str(moved))[1]
    assert np.allclose(meta["ifsforge_translation"], shift) and "ifsforge_translation" not in pyopenvdb.readAll(str(plain))[1]
    # The grid's box is centred on the file's origin: its first and last voxel centres are opposite.
    first, last = (np.asarray(pyopenvdb.read(str(moved), "density").transform.indexToWorld(ijk))
                   for ijk in ((0, 0, 0), tuple(int(d) - 1 for d in volume.dims)))
    assert np.allclose(first, -last, atol=1e-12)


@pytest.mark.parametrize("name, grids", [("volume_tetrahedron_alpha", {"density", "alpha"}),
                                         ("volume_menger_gray", {"density", "color", "gray"}),
                                         ("volume_hsi_tower", {"density", "color"})])
def test_extra_channels_get_grids(tmp_path, samples, name, grids):
    volume = ifsforge.render_volume(ifsforge.load(str(samples / f"{name}.json")), "prr", 24)
    path = tmp_path / f"{name}.vdb"
    ifsforge.write_vdb(str(path), volume)
    found = pyopenvdb.readAll(str(path))[0]
    assert {g.name for g in found} == grids
    assert all(g.activeVoxelCount() == len(volume) for g in found)
    for attribute in volume.attributes().values():
        assert attribute.min() >= 0.0 and attribute.max() <= 1.0


def test_read_vdb_info_refuses_truncated_and_foreign_files(tmp_path):
    """OpenVDB reads on through a truncated .vdb with uninitialised sizes: ifsforge refuses it first."""
    volume = ifsforge.render_volume(constant_color_tetrahedron((0.2, 0.6, 0.9)), "prr", 8)
    path, cut = tmp_path / "whole.vdb", tmp_path / "cut.vdb"
    ifsforge.write_vdb(str(path), volume)
    data = path.read_bytes()
    for size in (0, 4, 8, 16, 64, len(data) // 2, len(data) - 1):
        cut.write_bytes(data[:size])
        with pytest.raises(ifsforge.FileError):
            ifsforge.read_vdb_info(str(cut))
    cut.write_text("not a volume\n")
    with pytest.raises(ifsforge.FileError):
        ifsforge.read_vdb_info(str(cut))
    for _ in range(3):
        assert [g["active_voxels"] for g in ifsforge.read_vdb_info(str(path))["grids"]] == [len(volume)] * 2


def test_mesh_dict_feeds_write_mesh(tmp_path):
    volume = ifsforge.render_volume(constant_color_tetrahedron((0.2, 0.6, 0.9)), "prr", 32)
    mesh = ifsforge.volume_to_mesh(volume)
    assert mesh["triangles"].shape[1] == 3 and mesh["triangles"].max() < len(mesh["positions"])
    lo, hi = np.asarray(volume.bounds[:3]), np.asarray(volume.bounds[3:])
    assert np.all(mesh["positions"] >= lo - 1e-6) and np.all(mesh["positions"] <= hi + 1e-6)
    assert np.allclose(mesh["colors"], [0.2, 0.6, 0.9, 1.0], atol=1e-5)
    path = tmp_path / "tetra.glb"
    ifsforge.write_mesh(str(path), **mesh)
    assert path.stat().st_size > 1000


def test_progress_and_cancellation():
    tetra = constant_color_tetrahedron((1, 0, 0))
    seen = []
    ifsforge.render_volume(tetra, "prr", 32, progress=lambda f: seen.append(f) or True)
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(ifsforge.Cancelled):
        ifsforge.render_volume(tetra, "ria", 32, progress=lambda f: False)


def openvdb_mesh(volume, adaptivity):
    """OpenVDB's own volumeToMesh (pyopenvdb's convertToPolygons) of the volume's occupancy."""
    grid = pyopenvdb.FloatGrid()
    grid.gridClass = pyopenvdb.GridClass.FOG_VOLUME
    h = volume.voxel_size
    grid.transform = pyopenvdb.createLinearTransform(
        [[h, 0, 0, 0], [0, h, 0, 0], [0, 0, h, 0], [*(o + 0.5 * h for o in volume.origin), 1]])
    accessor = grid.getAccessor()
    for ijk in volume.coords:
        accessor.setValueOn(tuple(int(c) for c in ijk), 1.0)
    return grid.convertToPolygons(isovalue=0.5, adaptivity=adaptivity)


@pytest.mark.parametrize("adaptivity", [0.0, 0.5])
def test_iso_surface_is_openvdbs_mesh(samples, adaptivity):
    """The mesher runs OpenVDB's stages job by job (to hear Ctrl-C): the same points in the same
    order, OpenVDB's triangles then its quads as two triangles (a, b, c), (a, c, d), reversed
    to face out of a fog volume."""
    volume = ifsforge.render_volume(ifsforge.load(str(samples / "menger_sponge.json")), "prr", 40)
    mesh = ifsforge.volume_to_mesh(volume, adaptivity=adaptivity)
    points, triangles, quads = openvdb_mesh(volume, adaptivity)
    # Equal up to how the two transforms round (an affine matrix here, scale then shift there).
    assert mesh["positions"].shape == points.shape
    assert np.allclose(mesh["positions"], points, rtol=0, atol=1e-12)
    expected = np.concatenate([triangles[:, ::-1],
                               np.stack([quads[:, [2, 1, 0]], quads[:, [2, 0, 3]]], axis=1).reshape(-1, 3)])
    assert np.array_equal(mesh["triangles"], expected)
    assert (len(triangles) > 0) == (adaptivity > 0)


def test_iso_surface_does_not_depend_on_the_thread_count(samples):
    volume = ifsforge.render_volume(ifsforge.load(str(samples / "volume_sierpinski_pyramid_rgb.json")), "prr", 48)
    meshes = []
    try:
        for threads in (1, 3):
            ifsforge.set_default_threads(threads)
            meshes.append(ifsforge.volume_to_mesh(volume))
    finally:
        ifsforge.set_default_threads(0)
    assert meshes[0]["colors"] is not None
    for key in ("positions", "triangles", "normals", "colors"):
        assert np.array_equal(meshes[0][key], meshes[1][key]), key
    assert ifsforge.volume_to_mesh(volume, normals=False)["normals"] is None


def test_iso_surface_reports_progress_and_cancels():
    volume = ifsforge.render_volume(constant_color_tetrahedron((1, 0, 0)), "prr", 32)
    seen = []
    ifsforge.volume_to_mesh(volume, progress=lambda f: seen.append(f) or True)
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(ifsforge.Cancelled):
        ifsforge.volume_to_mesh(volume, progress=lambda f: False)


def test_mesh_writers_report_progress_and_cancel(tmp_path):
    mesh = ifsforge.volume_to_mesh(ifsforge.render_volume(constant_color_tetrahedron((1, 0, 0)), "prr", 32))
    for ext in ("ply", "obj", "glb"):
        written = []
        ifsforge.write_mesh(str(tmp_path / f"m.{ext}"), **mesh, progress=lambda f: written.append(f) or True)
        assert written and written[-1] == 1.0 and written == sorted(written)
        with pytest.raises(ifsforge.Cancelled):
            ifsforge.write_mesh(str(tmp_path / f"cancelled.{ext}"), **mesh, progress=lambda f: False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.glb", "m.obj", "m.ply"]


def test_cli_writes_vdb_and_mesh(cli, tmp_path, samples):
    r = cli("volume", samples / "volume_sierpinski_pyramid_rgb.json", "--res", "40", "-o", tmp_path / "p.vdb",
            "--mesh", tmp_path / "p.ply", check=True)
    occupied = int(r.stdout.split(" occupied")[0].split()[-1].replace(",", ""))
    assert pyopenvdb.read(str(tmp_path / "p.vdb"), "density").activeVoxelCount() == occupied
    assert (tmp_path / "p.ply").stat().st_size > 1000
    r = cli("volume", samples / "menger_sponge.json", "--res", "27", "--bounds", "0", "0", "0", "1", "1", "1",
            "--depth", "3", "-o", tmp_path / "m.vdb", check=True)
    assert pyopenvdb.read(str(tmp_path / "m.vdb"), "density").activeVoxelCount() == 8000


def test_a_vdb_alone_is_written_straight_from_the_render(cli, tmp_path, samples):
    # -o alone: PRR gives the file its volume band by band; with --mesh the volume is built whole
    # first. The same bytes, as from Python.
    path = samples / "volume_sierpinski_pyramid_rgb.json"
    cli("volume", path, "--res", "200", "-o", tmp_path / "alone.vdb", check=True)
    cli("volume", path, "--res", "200", "-o", tmp_path / "whole.vdb", "--mesh", tmp_path / "m.ply", check=True)
    assert (tmp_path / "alone.vdb").read_bytes() == (tmp_path / "whole.vdb").read_bytes()
    system = ifsforge.load(str(path))
    seen = []
    made = ifsforge.render_volume_to_vdb(str(tmp_path / "straight.vdb"), system, "prr", resolution=200, compress=True,
                                         progress=lambda f: seen.append(f) or True)
    assert seen[-1] == 1.0 and any(0.95 < f < 1.0 for f in seen)  # the writing is the last 5%
    volume = ifsforge.render_volume(system, "prr", resolution=200)
    ifsforge.write_vdb(str(tmp_path / "rendered.vdb"), volume, system=system, compress=True)
    assert (tmp_path / "straight.vdb").read_bytes() == (tmp_path / "rendered.vdb").read_bytes()
    assert made["voxels"] == len(volume) > 100000 and made["points"] == volume.points
    assert made["dims"] == tuple(volume.dims) and made["depth"] == volume.depth
    grid = pyopenvdb.read(str(tmp_path / "straight.vdb"), "color")
    assert grid.activeVoxelCount() == len(volume)
    with pytest.raises(TypeError, match="unexpected keyword argument 'colour'"):
        ifsforge.render_volume_to_vdb(str(tmp_path / "x.vdb"), system, "prr", colour=1)
    assert not (tmp_path / "x.vdb").exists()
    with pytest.raises(ifsforge.Cancelled):  # cancelled while writing: no file
        ifsforge.render_volume_to_vdb(str(tmp_path / "x.vdb"), system, "prr", resolution=200, progress=lambda f: f < 0.96)
    assert not list(tmp_path.glob("x.vdb*"))


def test_cli_refuses_bad_input(cli, tmp_path, samples):
    divergent = tmp_path / "divergent.json"
    divergent.write_text(json.dumps({"format": "ifsforge/1", "name": "blow-up", "layout": "xyz", "maps": [
        {"matrix": [[1.5, 0, 0], [0, 1.5, 0], [0, 0, 1.5]], "offset": [0, 0, 0], "probability": 0.5},
        {"matrix": [[1.2, 0, 0], [0, 1.2, 0], [0, 0, 1.2]], "offset": [1, 0, 0], "probability": 0.5}]}))
    out = tmp_path / "out.vdb"
    cases = [((samples / "barnsley_fern.json", "-o", out), "3D system"),
             ((samples / "menger_sponge.json", "--res", "0", "-o", out), "argument --res: expects 1..16384"),
             ((samples / "menger_sponge.json", "--res", "99999", "-o", out), "argument --res: expects 1..16384"),
             ((divergent, "-o", out), "divergent"),
             ((samples / "menger_sponge.json", "-o", tmp_path / "out.png"), ".vdb"),
             ((samples / "menger_sponge.json", "-o", tmp_path / "missing" / "out.vdb"), "does not exist"),
             ((samples / "volume_fern_3d.json", "-a", "eta", "-o", out), "singular")]
    for args, expected in cases:
        r = cli("volume", *args)
        assert r.returncode == 2, (args, r.stderr)
        assert expected in r.stderr, (args, r.stderr)
        # One line, or the parser's usage and its one line.
        assert len(r.stderr.strip().splitlines()) == 1 or r.stderr.startswith("usage: ifsforge volume")
    assert not list(tmp_path.glob("out*")) and not (tmp_path / "missing").exists()


def test_blender_imports_the_volume(tmp_path):
    """Blender 3.4 reads our .vdb as a Volume object with 'density' and 'color' grids, places it
    where the IFS puts it, and its Principled Volume renders it in the volume's colour."""
    rgb = (0.9, 0.15, 0.1)
    volume = ifsforge.render_volume(constant_color_tetrahedron(rgb), "prr", 48)
    path = tmp_path / "tinted.vdb"
    ifsforge.write_vdb(str(path), volume)
    h = volume.voxel_size
    box = list(volume.positions.min(axis=0) - h / 2) + list(volume.positions.max(axis=0) + h / 2)
    script = ROOT / "tests" / "blender" / "volume_import.py"
    r = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python", str(script),
                        "--", str(path), str(h), *map(str, box), *map(str, rgb)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    assert "OK grids ['color', 'density']" in r.stdout
