"""ifsforge.mesh_edges (what the Blender add-on hands Blender instead of letting it derive the
edges) and ifsforge.set_default_threads."""
import numpy as np
import pytest

import ifsforge
from conftest import ROOT


def grid_quads(n):
    r, c = np.mgrid[0:n - 1, 0:n - 1]
    v = (r * n + c).ravel()
    return np.stack([v, v + 1, v + n + 1, v + n], 1).astype(np.uint32)


def test_grid_of_quads_has_the_counted_edges_in_blender_order():
    n = 9
    edges, corner_edges = ifsforge.mesh_edges(grid_quads(n), n * n)
    assert edges.dtype == np.uint32 and corner_edges.dtype == np.uint32  # Blender's bulk format
    assert edges.shape == (2 * n * (n - 1), 2) and corner_edges.shape == (4 * (n - 1) ** 2,)
    assert (edges[:, 0] < edges[:, 1]).all()
    assert (np.diff(edges[:, 0].astype(np.int64) * n * n + edges[:, 1]) > 0).all()  # sorted, unique
    # Every corner's edge joins that corner's vertex and the next one of its face.
    faces = grid_quads(n)
    a, b = faces.ravel(), np.roll(faces, -1, axis=1).ravel()
    np.testing.assert_array_equal(edges[corner_edges], np.stack([np.minimum(a, b), np.maximum(a, b)], 1))


def test_bad_faces_name_the_problem():
    with pytest.raises(ifsforge.InputError, match="vertex 9"):
        ifsforge.mesh_edges(np.array([[0, 1, 9]]), 4)
    with pytest.raises(ifsforge.InputError, match="shape"):
        ifsforge.mesh_edges(np.array([0, 1, 2]), 4)


def test_default_threads_do_not_change_outputs():
    system = ifsforge.read_json(str(ROOT / "samples" / "systems" / "sierpinski_triangle.json"))
    reference = ifsforge.render(system, "chaos", 64, seed=3).to_image("density")
    try:
        ifsforge.set_default_threads(1)
        assert ifsforge.default_threads() == 1
        single = ifsforge.render(system, "chaos", 64, seed=3).to_image("density")
    finally:
        ifsforge.set_default_threads(0)
    np.testing.assert_array_equal(reference, single)
    with pytest.raises(ifsforge.InputError, match="threads"):
        ifsforge.set_default_threads(-2)


def test_edges_do_not_depend_on_the_thread_count():
    # Each thread owns a block of vertices; the edges come in one pass's order whatever the blocks.
    volume = ifsforge.render_volume(ifsforge.read_json(str(ROOT / "samples" / "systems" / "menger_sponge.json")),
                                    "prr", 60)
    faces = ifsforge.volume_to_mesh(volume)["triangles"]
    count = int(faces.max()) + 1
    results = []
    try:
        for threads in (1, 3):
            ifsforge.set_default_threads(threads)
            results.append(ifsforge.mesh_edges(faces, count))
    finally:
        ifsforge.set_default_threads(0)
    (edges, corners), (edges3, corners3) = results
    np.testing.assert_array_equal(edges, edges3)
    np.testing.assert_array_equal(corners, corners3)
    # Every corner's edge joins its vertex and the next corner's, low vertex first.
    ends = np.sort(np.stack([faces.ravel(), np.roll(faces, -1, axis=1).ravel()], axis=1), axis=1)
    np.testing.assert_array_equal(edges[corners], ends)
    assert np.all(np.diff(edges[:, 0].astype(np.int64) * count + edges[:, 1]) > 0)  # sorted, each once
