"""The axes and colour rules of docs/formats.md, end to end: the CLI writes the files, real Blender imports
them with its importers' default settings (tests/blender/mesh_axes_import.py)."""
import json
import re
import shutil
import struct

import numpy as np
import pytest

import ifsforge
from conftest import ROOT
from test_blender_addon import run_blender

TERRAIN = ROOT / "samples" / "terrain" / "ridge_range.json"


def read_glb(path):
    """(JSON, binary chunk) of a .glb."""
    data = path.read_bytes()
    length = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + length]), data[28 + length:]


def glb_attribute(gltf, binary, index, components):
    accessor = gltf["accessors"][index]
    view = gltf["bufferViews"][accessor["bufferView"]]
    start = view.get("byteOffset", 0) + accessor.get("byteOffset", 0)
    return np.frombuffer(binary, np.float32, accessor["count"] * components, start).reshape(-1, components)


def test_cli_up_turns_every_mesh_output(cli, tmp_path, samples):
    """Default: the format's axis; --up overrides it (the pyramid's apex is the file's top)."""
    pyramid = samples / "sierpinski_pyramid.json"
    for up, name in ((None, "default.glb"), ("z", "z.glb")):
        cli("volume", pyramid, "--res", "16", "--mesh", name, *(["--up", up] if up else []), check=True)
        gltf, _ = read_glb(tmp_path / name)
        accessor = gltf["accessors"][gltf["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
        lo, hi = accessor["min"], accessor["max"]
        up_axis, north = (1, 2) if up is None else (2, 1)  # y up: (x, z, -y)
        # The apex 0.707 above a unit square base, to within a voxel (1/16 + padding).
        assert abs(lo[up_axis]) < 0.1 and abs(hi[up_axis] - 0.7071) < 0.1, (name, lo, hi)
        span = (-hi[north], -lo[north]) if up is None else (lo[north], hi[north])
        assert abs(span[0]) < 0.1 and abs(span[1] - 1) < 0.1, (name, lo, hi)
    cli("volume", pyramid, "--res", "16", "--mesh", "y.ply", "--up", "y", check=True)
    cli("volume", pyramid, "--res", "16", "--mesh", "z.ply", check=True)
    y, z = ifsforge.read_mesh(str(tmp_path / "y.ply")), ifsforge.read_mesh(str(tmp_path / "z.ply"))
    np.testing.assert_allclose(y["positions"], z["positions"][:, [0, 2, 1]] * [1, 1, -1], atol=1e-6)
    cli("instances", pyramid, "--depth", "1", "--gltf", "i.glb", "--up", "z", check=True)
    gltf, _ = read_glb(tmp_path / "i.glb")
    expected = ifsforge.instances(ifsforge.load(str(pyramid)), depth=1).positions
    np.testing.assert_allclose([n["translation"] for n in gltf["nodes"][1:]], expected, atol=1e-6)
    r = cli("terrain", TERRAIN, "--res", "9", "-o", "t.obj", "--up", "x")
    assert r.returncode == 2 and "--up" in r.stderr


def test_every_mesh_stands_upright_in_blender(cli, tmp_path, samples):
    pyramid = samples / "sierpinski_pyramid.json"
    files = []
    volume = ifsforge.render_volume(ifsforge.load(str(pyramid)), "prr", 32)
    h = volume.voxel_size
    box = list(volume.positions.min(axis=0) - h / 2) + list(volume.positions.max(axis=0) + h / 2)
    for ext in (".glb", ".obj", ".ply"):
        cli("volume", pyramid, "--res", "32", "--mesh", f"iso{ext}", check=True)
        # The iso-surface of the occupancy runs through the outer voxels' centres, give or take.
        files.append({"path": str(tmp_path / f"iso{ext}"), "box": box, "tolerance": 1.01 * h,
                      "top": [0.5, 0.5], "top_tolerance": 1.5 * h})
    cli("terrain", TERRAIN, "--res", "65x49", "-o", "t.glb", "-o", "t.obj", "-o", "t.ply", check=True)
    terrain = ifsforge.make_terrain(ifsforge.read_terrain_recipe(str(TERRAIN)).controls, 65, 49)
    positions = terrain.positions().reshape(-1, 3)
    top = positions[np.argmax(positions[:, 2])]
    box = list(positions.min(axis=0)) + list(positions.max(axis=0))
    assert box[5] - box[2] < min(box[3] - box[0], box[4] - box[1]) / 3  # height clearly the smallest extent
    for ext in (".glb", ".obj", ".ply"):
        files.append({"path": str(tmp_path / f"t{ext}"), "box": box, "tolerance": 1e-4,
                      "top": top[:2].tolist(), "top_tolerance": 1e-4})
    cli("instances", pyramid, "--depth", "2", "--gltf", "i.glb", check=True)
    inst = ifsforge.instances(ifsforge.load(str(pyramid)), depth=2)
    gltf, _ = read_glb(tmp_path / "i.glb")  # node k + 1 is instance k, named by its address
    nodes = {n["name"]: p.tolist() for n, p in zip(gltf["nodes"][1:], inst.positions)}
    assert max(nodes.values(), key=lambda p: p[2])[:2] == pytest.approx([0.5, 0.5], abs=0.2)  # the apex cluster
    files.append({"path": str(tmp_path / "i.glb"), "nodes": nodes})
    (tmp_path / "axes.json").write_text(json.dumps(files))
    report = run_blender("mesh_axes_import.py", tmp_path, timeout=300)
    assert len(report["checks"]) == 7


DISPLAY = np.array([0.8, 0.2, 0.4])  # on the 16-level grid of the instance materials and exact in 8 bits


def color_rule_system(path):
    """A Sierpinski tetrahedron whose maps set constant colours: DISPLAY on pieces 0 and 3 (all of
    the attractor with x, y < 0.5), (0, 1, 0) and (1, 0, 1) on the others, so that every channel
    spans [0, 1] and the Eq. 101 stretch leaves the colours as they are."""
    colours = [DISPLAY, (0, 1, 0), (1, 0, 1), DISPLAY]
    corners = ([0, 0, 0], [0.5, 0, 0], [0, 0.5, 0], [0, 0, 0.5])
    maps = [{"scale": [0.5] * 3, "rotation": [0, 0, 0], "translation": t,
             "channels": [[0, 0, 0, 0, 0, 0, float(c)] for c in rgb]} for t, rgb in zip(corners, colours)]
    path.write_text(json.dumps({"format": "ifsforge/1", "name": "colour rule", "layout": "xyz+rgb",
                                "probabilities": "uniform", "maps": maps}))
    return path


def corner(points):
    points = np.asarray(points)
    return (points[:, 0] < 0.45) & (points[:, 1] < 0.45)


def assert_display(display, what):
    display = np.asarray(display, float).reshape(-1, 3)
    assert len(display) > 0, what
    error = np.abs(display - DISPLAY).max()
    assert error <= 1 / 255, f"{what}: off by {error * 255:.2f}/255"


def test_one_color_through_every_file(cli, tmp_path):
    system = color_rule_system(tmp_path / "rule.json")
    linear = ifsforge.srgb_to_linear(DISPLAY)
    assert np.all(np.abs(linear - DISPLAY) > 0.1)  # the test can tell linear from display values
    # PNG: display values as they are (top view, x right, y up).
    cli("render", system, "-o", "p.png", "--size", "64", "--mode", "color", "--view", "0", "90",
        "--window", "0", "0", "1", "1", check=True)
    image = ifsforge.read_png(str(tmp_path / "p.png"))
    rows, columns = np.mgrid[0:64, 0:64]
    centres = np.stack([(columns + 0.5) / 64, 1 - (rows + 0.5) / 64], -1).reshape(-1, 2)
    covered = image.reshape(-1, 3).sum(-1) > 0
    assert_display(image.reshape(-1, 3)[corner(centres) & covered], "png")
    # .vdb: the colour grid linear; iso .glb: COLOR_0 linear; iso .ply: 8-bit display values.
    cli("volume", system, "--res", "32", "-o", "v.vdb", "--mesh", "iso.glb", check=True)
    cli("volume", system, "--res", "32", "--mesh", "iso.ply", check=True)
    pyopenvdb = pytest.importorskip("pyopenvdb")
    volume = ifsforge.render_volume(ifsforge.load(str(system)), "prr", 32)
    grid = pyopenvdb.read(str(tmp_path / "v.vdb"), "color").getConstAccessor()
    inside = corner(volume.positions)
    assert_display(ifsforge.linear_to_srgb([grid.getValue(tuple(map(int, c))) for c in volume.coords[inside]]),
                   "vdb")
    gltf, binary = read_glb(tmp_path / "iso.glb")
    attributes = gltf["meshes"][0]["primitives"][0]["attributes"]
    stored = glb_attribute(gltf, binary, attributes["POSITION"], 3)
    positions = np.stack([stored[:, 0], -stored[:, 2], stored[:, 1]], 1)  # the file holds (x, z, -y)
    colours = glb_attribute(gltf, binary, attributes["COLOR_0"], 4)[:, :3]
    assert_display(ifsforge.linear_to_srgb(colours[corner(positions)]), "iso glb")
    # Instances: .glb baseColorFactor linear, POV-Ray srgb as it is.
    cli("instances", system, "--depth", "2", "--gltf", "i.glb", "--pov", "i.pov", check=True)
    gltf, _ = read_glb(tmp_path / "i.glb")
    factors = [gltf["materials"][gltf["meshes"][n["mesh"]]["primitives"][0]["material"]]["pbrMetallicRoughness"]
               ["baseColorFactor"][:3] for n in gltf["nodes"][1:] if corner([[n["translation"][0],
                                                                             -n["translation"][2]]])[0]]
    assert len(factors) == 8
    assert_display(ifsforge.linear_to_srgb(factors), "instance glb")
    spheres = re.findall(r"sphere\{<([^>]*)>,[^ ]* pigment\{srgb<([^>]*)>\}\}", (tmp_path / "i.pov").read_text())
    assert len(spheres) == 16
    srgb = [[float(v) for v in c.split(",")] for p, c in spheres if corner([[float(v) for v in p.split(",")]])[0]]
    assert len(srgb) == 8
    assert_display(srgb, "POV-Ray")
    if shutil.which("blender") is None:
        pytest.skip("Blender is not installed: the add-on and Blender's importers are not checked")
    (tmp_path / "colour.json").write_text(json.dumps({
        "system": str(system), "display": DISPLAY.tolist(), "iso_glb": str(tmp_path / "iso.glb"),
        "iso_ply": str(tmp_path / "iso.ply"), "instances_glb": str(tmp_path / "i.glb")}))
    report = run_blender("color_rule.py", tmp_path, timeout=300)
    # The add-on's own .vdb holds the same linear colour.
    path = report["values"]["addon_vdb"]
    grid = pyopenvdb.read(path, "color").getConstAccessor()
    assert_display(ifsforge.linear_to_srgb([grid.getValue(tuple(map(int, c))) for c in volume.coords[inside]]),
                   "add-on vdb")
