"""Mesh targets and primitives from hand-made files: a reader's refusal says what is wrong and
where (which vertex, which face, which index), and OpenMesh's own lines never reach stderr."""
import pytest

import ifsforge

TRIANGLE_PLY_HEAD = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")
STL_FACET = "facet normal 0 0 1\nouter loop\nvertex {}\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"


@pytest.mark.parametrize("name,text,message", [
    ("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", r"nan\.obj': vertex 1 has a non-finite coordinate"),
    ("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n", r"inf\.obj': vertex 2 has a non-finite coordinate"),
    ("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 99\n",
     r"range\.obj':5: face 1 refers to vertex 99 but the file has 3 vertices"),
    ("nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", r"nan\.off': vertex 1 has a non-finite coordinate"),
    ("range.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 99\n",
     r"range\.off': face 1 refers to vertex 99 but the file has 3 vertices"),
    ("word.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 one 2\n", r"word\.off': face 0 has a vertex index 'one'"),
    ("nan.ply", TRIANGLE_PLY_HEAD + "0 0 0\n1 0 0\n0 nan 0\n3 0 1 2\n",
     r"nan\.ply': vertex 2 has a non-finite coordinate"),
    ("range.ply", TRIANGLE_PLY_HEAD + "0 0 0\n1 0 0\n0 1 0\n3 0 1 99\n",
     r"range\.ply': face 0 refers to vertex 99 but the file has 3 vertices"),
    ("negative.ply", TRIANGLE_PLY_HEAD + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n",
     r"negative\.ply': face 0 refers to vertex -1 but the file has 3 vertices"),
    ("nan.stl", "solid s\n" + STL_FACET.format("0 0 0") + STL_FACET.format("nan 0 0") + "endsolid s\n",
     r"nan\.stl': vertex \d+ has a non-finite coordinate"),
])
def test_mesh_errors_say_what_and_where(tmp_path, capfd, name, text, message):
    (tmp_path / name).write_text(text)
    with pytest.raises(ifsforge.InputError, match=message):
        ifsforge.read_mesh(str(tmp_path / name))
    assert capfd.readouterr().err == ""


def test_a_file_of_vertices_only_says_so(tmp_path, capfd):
    (tmp_path / "points.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\n")
    with pytest.raises(ifsforge.InputError, match=r"points\.obj' has no faces \(it holds 3 vertices"):
        ifsforge.read_mesh(str(tmp_path / "points.obj"))
    assert capfd.readouterr().err == ""


def test_openmesh_lines_are_captured_not_printed(tmp_path, capfd):
    # Three triangles on one edge: OpenMesh prints "PolyMeshT::add_face: complex edge" on its
    # error stream and duplicates the vertices; the mesh is read, and nothing reaches stderr.
    (tmp_path / "fin.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 1 2 4\nf 1 2 3\n")
    mesh = ifsforge.read_mesh(str(tmp_path / "fin.obj"))
    assert len(mesh["triangles"]) == 3
    assert capfd.readouterr().err == ""


def test_fit_names_the_bad_vertex_of_a_mesh_target(cli, tmp_path):
    (tmp_path / "target.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 nan\nf 1 2 3\nf 1 2 4\n")
    result = cli("fit", "target.obj", "-o", "f.json")
    assert result.returncode == 2, result.stderr
    assert "vertex 3 has a non-finite coordinate" in result.stderr and "Traceback" not in result.stderr
    assert not (tmp_path / "f.json").exists()
