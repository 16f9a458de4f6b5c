"""Vector IFS through the binding and the CLI: instance arrays against numpy compositions of the
maps, the exporters against their consumers (xml.etree for SVG, real POV-Ray, Blender's glTF
importer), and bad input."""
import json
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

import ifsforge

BLENDER_SCRIPT = Path(__file__).resolve().parents[1] / "blender" / "vector_gltf_import.py"


def composed(system, address, point):
    """w_a0(w_a1(...(point))) with numpy, innermost map first."""
    p = np.asarray(point, float)
    for a in reversed(address):
        m = system.maps[a]
        p = m.matrix @ p + m.offset
    return p


def test_instance_arrays_are_compositions_of_the_address(samples):
    system = ifsforge.read_json(str(samples / "vector_csg_pyramid.json"))
    base = [0.4, 0.3, 0.2, 0.1, 0.2, 0.3, 0.0]
    inst = ifsforge.instances(system, depth=3, primitives="sphere,box,cone", base_point=base,
                              base_vector=[0, 0, 0.5], normalization="constant", length=0.05)
    assert len(inst) == 5 ** 3
    digits = inst.addresses.digits
    assert digits.shape == (125, 3) and digits.dtype == np.uint16
    for i in range(len(inst)):
        p = composed(system, list(digits[i]), base)
        np.testing.assert_allclose(inst.positions[i], p[:3], atol=1e-6)
        assert inst.primitive[i] == round(p[6]) % 3  # Eq. 107: the k channel picks the primitive
    # Eq. 60-62 with a constant length: qh = q0 + d e1 lies 0.05 from q0.
    qh = inst.positions + inst.scales[:, None] * inst.frames[:, 0, :]
    np.testing.assert_allclose(np.linalg.norm(qh - inst.positions, axis=1), 0.05, atol=1e-6)
    # Frames are rotations.
    np.testing.assert_allclose(inst.frames @ inst.frames.transpose(0, 2, 1), np.broadcast_to(np.eye(3), (125, 3, 3)), atol=1e-6)
    np.testing.assert_allclose(np.linalg.det(inst.frames), 1.0, atol=1e-6)
    # The structured array holds the same data.
    table = inst.to_numpy()
    assert table.dtype.names == ("position", "frame", "scale", "primitive", "color", "probability", "length", "address")
    np.testing.assert_array_equal(table["position"], inst.positions)
    np.testing.assert_array_equal(table["address"], digits)
    np.testing.assert_allclose(table["probability"].sum(), 1.0)
    with pytest.raises(ValueError):
        inst.positions[0, 0] = 1.0  # read-only views of the C++ list


def test_string_rewriting_tsa_and_instances_name_the_same_pieces(samples):
    system = ifsforge.read_json(str(samples / "sierpinski_tetrahedron.json"))
    strings = ifsforge.string_rewriting(system, 3)
    tsa = ifsforge.tesseral_synecdoche(system, 3)
    inst = ifsforge.instances(system, depth=3)
    assert sorted(strings) == tsa.addresses.strings() == inst.addresses.strings()
    start = system.start_point()
    for i, address in enumerate(tsa.addresses.strings()):
        digits = [int(d) for d in address.split(".")]
        np.testing.assert_allclose(tsa.points[i], composed(system, digits, start), atol=1e-9)
        np.testing.assert_allclose(ifsforge.apply_address(system, digits, start), tsa.points[i], atol=1e-12)


def test_tsa_pruning_keeps_the_measure(samples):
    fern = ifsforge.read_json(str(samples / "barnsley_fern.json"))
    leaves = ifsforge.tesseral_synecdoche(fern, 30, min_probability=1e-4)
    p = leaves.addresses.probabilities
    assert abs(p.sum() - 1.0) < 1e-9
    assert ((leaves.addresses.lengths == 30) | (p < 1e-4)).all()
    assert len(leaves) == ifsforge.count_leaves(fern, 30, 1e-4)


def test_svg_parses_with_one_element_per_instance(samples, tmp_path):
    system = ifsforge.read_json(str(samples / "vector_triangles_squares.json"))
    inst = ifsforge.instances(system, depth=4, primitives="triangle,square-outline", base_point=[0, 0, 0],
                              base_vector=[1, 0])
    path = tmp_path / "t.svg"
    ifsforge.write_svg(str(path), inst, width=300, title="a <b> & c")
    root = ET.parse(path).getroot()
    ns = {"s": "http://www.w3.org/2000/svg"}
    assert root.get("width") == "300"
    polygons = root.findall(".//s:polygon", ns)
    assert len(polygons) == len(inst) == 256
    assert sum(p.get("fill") == "none" for p in polygons) == int((inst.primitive == 1).sum())
    assert root.find("s:title", ns).text == "a <b> & c"
    # Every polygon corner lies inside the viewBox.
    w, h = (float(v) for v in root.get("viewBox").split()[2:])
    for p in polygons:
        xy = np.array([[float(v) for v in pair.split(",")] for pair in p.get("points").split()])
        assert (xy >= -1e-9).all() and (xy[:, 0] <= w).all() and (xy[:, 1] <= h).all()
    with pytest.raises(ifsforge.InputError, match="2D"):
        ifsforge.write_svg(str(tmp_path / "x.svg"), ifsforge.instances(ifsforge.read_json(str(samples / "menger_sponge.json")), depth=1))
    assert not (tmp_path / "x.svg").exists()


def test_cli_writes_every_output_and_povray_renders_it(cli, samples, tmp_path):
    r = cli("instances", samples / "vector_csg_pyramid.json", "--depth", "2", "--primitive", "sphere,box,cone",
            "--pov", "s.pov", "--render", "s.png", "--size", "96x72", "--npy", "s.npy", "--csv", "s.csv",
            "--gltf", "s.glb", "--png", "d.png", check=True)
    assert "25 instances of sphere, box, cone" in r.stdout
    for name in ("s.pov", "ifsforge.inc", "s.png", "s.npy", "s.csv", "s.glb", "d.png"):
        assert (tmp_path / name).stat().st_size > 0, name
    image = ifsforge.read_png(str(tmp_path / "s.png"))
    assert image.shape[:2] == (72, 96)
    table = np.load(tmp_path / "s.npy")
    assert len(table) == 25 and table["address"].shape == (25, 2)
    rows = (tmp_path / "s.csv").read_text().splitlines()
    assert rows[0] == "index,address,length,probability" and rows[1].startswith("0,0.0,2,") and len(rows) == 26
    assert (tmp_path / "ifsforge.inc").read_text() == ifsforge.povray_include()
    glb = (tmp_path / "s.glb").read_bytes()
    assert glb[:4] == b"glTF"
    gltf = json.loads(glb[20:20 + int.from_bytes(glb[12:16], "little")])
    assert len(gltf["nodes"]) == 26 and len(gltf["nodes"][0]["children"]) == 25


def test_hostile_system_names_stay_inert_in_the_scene(cli, samples, tmp_path):
    text = (samples / "sierpinski_triangle.json").read_text()
    hostile = json.loads(text)
    hostile["name"] = '"; #system "rm\n#declare Boom = 1/0;'
    (tmp_path / "hostile.json").write_text(json.dumps(hostile))
    cli("instances", "hostile.json", "--depth", "2", "--pov", "h.pov", "--render", "h.png", "--size", "32x24",
        check=True)
    scene = (tmp_path / "h.pov").read_text()
    assert "\n#declare Boom" not in scene
    assert '#declare IFS_Title = "IFS instances: \\"; #system \\"rm #declare Boom = 1/0;";' in scene


def test_cli_bad_input_fails_cleanly(cli, samples, tmp_path):
    r = cli("instances", samples / "menger_sponge.json", "--primitive", "dodecahedron", "--pov", "x.pov")
    assert r.returncode == 2 and "unknown primitive 'dodecahedron'" in r.stderr
    r = cli("instances", samples / "menger_sponge.json", "--render", "x.png")
    assert r.returncode == 2 and "--pov" in r.stderr
    r = cli("instances", samples / "menger_sponge.json", "--depth", "99", "--pov", "x.pov")
    assert r.returncode == 2 and "depth" in r.stderr
    r = cli("instances", samples / "menger_sponge.json", "--base-vector", "1", "0", "--pov", "x.pov")
    assert r.returncode == 2 and "base vector needs 3" in r.stderr
    r = cli("instances", samples / "menger_sponge.json", "--pov", "missing/x.pov")
    assert r.returncode == 2 and "does not exist" in r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_cancelled_render_leaves_no_image(samples, tmp_path):
    system = ifsforge.read_json(str(samples / "sierpinski_tetrahedron.json"))
    scene = tmp_path / "t.pov"
    ifsforge.write_pov_scene(str(scene), ifsforge.instances(system, depth=3))
    with pytest.raises(ifsforge.Cancelled):
        ifsforge.render_povray(str(scene), str(tmp_path / "t.png"), 64, 48, progress=lambda f: False)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["ifsforge.inc", "t.pov"]


def test_user_mesh_primitive_through_every_exporter(samples, tmp_path):
    leaf = tmp_path / "leaf.obj"
    leaf.write_text("v 0 0 0\nv 1 0 0\nv 0.5 0.3 0\nv 0.5 0.1 0.2\nf 1 2 3\nf 1 4 2\nf 2 4 3\nf 3 4 1\n")
    system = ifsforge.read_json(str(samples / "sierpinski_tetrahedron.json"))
    inst = ifsforge.instances(system, depth=2, primitives=["sphere", f"mesh:{leaf}"])
    assert inst.primitives[1].name == f"mesh:{leaf}"
    mesh = ifsforge.read_mesh(str(leaf))
    assert mesh["triangles"].shape == (4, 3)
    np.testing.assert_allclose(inst.primitives[1].bounding_radius, np.linalg.norm(mesh["positions"], axis=1).max())
    ifsforge.write_pov_scene(str(tmp_path / "m.pov"), inst)
    assert "#declare IFS_Mesh_leaf = mesh2" in (tmp_path / "m.pov").read_text()
    ifsforge.render_povray(str(tmp_path / "m.pov"), str(tmp_path / "m.png"), 48, 36)
    assert (tmp_path / "m.png").exists()


def test_blender_imports_the_gltf_as_linked_duplicates(samples, tmp_path):
    system = ifsforge.read_json(str(samples / "menger_sponge.json"))
    inst = ifsforge.instances(system, depth=2, primitives="box")  # first-map colours: 10 palette entries
    glb = tmp_path / "sponge.glb"
    ifsforge.write_gltf_instances(str(glb), inst)
    names = inst.addresses.strings()
    picks = (0, 57, len(inst) - 1)
    expected = {"root": inst.name, "count": len(inst), "meshes": 10,
                "positions": {names[i]: [float(v) for v in inst.positions[i]] for i in picks},
                "scales": {names[i]: float(inst.scales[i]) for i in picks}}
    (tmp_path / "expected.json").write_text(json.dumps(expected))
    result = subprocess.run(["blender", "-b", "--factory-startup", "--python-exit-code", "1", "--python",
                             str(BLENDER_SCRIPT), "--", str(glb), str(tmp_path / "expected.json")],
                            capture_output=True, text=True, timeout=240)
    assert result.returncode == 0 and "VECTOR_GLTF_OK 400 objects sharing 10 meshes" in result.stdout, \
        result.stdout[-2000:] + result.stderr[-2000:]
