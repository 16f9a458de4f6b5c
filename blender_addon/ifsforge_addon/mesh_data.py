"""Arrays from the ifsforge module into Blender meshes (bulk foreach_set, no per-element Python)."""
import numpy as np

import ifsforge


def prepare(data):
    """Adds "faces" and "edges" to a mesh dict of the core, on the worker thread. Faces: quads
    where the triangles come in pairs (a, b, c), (a, c, d) (terrain cells, the iso-surface's
    voxel faces), which Blender splits back along the same a-c diagonal, so the surface is the
    same with a third fewer corners; else the triangles. Edges: ifsforge.mesh_edges, which
    Blender would otherwise derive on the main thread, slower."""
    faces = np.ascontiguousarray(data["triangles"], np.uint32).reshape(-1, 3)
    if len(faces) and len(faces) % 2 == 0:
        pairs = faces.reshape(-1, 6)  # (a, b, c, a', c', d)
        if np.array_equal(pairs[:, 0], pairs[:, 3]) and np.array_equal(pairs[:, 2], pairs[:, 4]):
            quads = np.empty((len(pairs), 4), np.uint32)  # filled column by column: no temporaries, unlike column_stack
            quads[:, :3] = pairs[:, :3]
            quads[:, 3] = pairs[:, 5]
            faces = quads
    data["faces"] = faces
    data["edges"] = ifsforge.mesh_edges(data["faces"], len(data["positions"]))
    return data


def grid_faces(columns, rows):
    """Faces and edges of a columns x rows lattice (vertex r * columns + c), known without a
    search: one quad (a, b, c, d) per cell, corners (r, c), (r, c+1), (r+1, c+1), (r+1, c), which
    Blender splits along a-c, the diagonal of the core's two triangles (a, b, c), (a, c, d).
    Edges: the rows' horizontal edges first (index r * (columns - 1) + c), then the vertical ones
    (after them, index r * columns + c). Returns (faces (n, 4), (edges (E, 2), corner_edges))
    as uint32, the format fill_mesh takes."""
    w, h = columns, rows
    if w < 2 or h < 2:
        raise ifsforge.InputError(f"a grid of {w}x{h} samples has no cells")
    if w * h >= 2 ** 32:
        raise ifsforge.InputError(f"a grid of {w}x{h} samples is too big for 32-bit indices")
    u32 = np.uint32
    cell = (np.arange(h - 1, dtype=u32)[:, None] * u32(w) + np.arange(w - 1, dtype=u32)).ravel()
    faces = np.empty((len(cell), 4), u32)
    faces[:, 0] = cell
    faces[:, 1] = cell + u32(1)
    faces[:, 2] = cell + u32(w + 1)
    faces[:, 3] = cell + u32(w)
    horizontal = h * (w - 1)
    edges = np.empty((horizontal + (h - 1) * w, 2), u32)
    start = (np.arange(h, dtype=u32)[:, None] * u32(w) + np.arange(w - 1, dtype=u32)).ravel()
    edges[:horizontal, 0] = start
    edges[:horizontal, 1] = start + u32(1)
    edges[horizontal:, 0] = np.arange((h - 1) * w, dtype=u32)
    edges[horizontal:, 1] = edges[horizontal:, 0] + u32(w)
    # The edge of each corner j (from corner j to j + 1), cell (r, c) = cell index r * (w - 1) + c.
    rows_of = np.repeat(np.arange(h - 1, dtype=u32), w - 1)
    below = cell - rows_of  # r * (w - 1) + c: the horizontal edge under the cell
    corner_edges = np.empty((len(cell), 4), u32)
    corner_edges[:, 0] = below
    corner_edges[:, 1] = u32(horizontal) + cell + u32(1)
    corner_edges[:, 2] = below + u32(w - 1)
    corner_edges[:, 3] = u32(horizontal) + cell
    return faces, (edges, corner_edges.ravel())


def fill_mesh(mesh, positions, faces, normals=None, uvs=None, colors=None, color_name="ifs_color",
              smooth=True, custom_normals=False, edges=None):
    """Replaces `mesh`'s geometry by faces (n, 3 or 4) over positions; optional uvs (per vertex,
    as the layer "UVMap") and display RGB(A) colours (a colour attribute stored linear, set by set_colors). The core's
    meshes index only their own vertices and have no degenerate faces, so no validate(): that
    alone took seconds on a 1025^2 terrain. Smooth shading uses the normals Blender derives from
    the faces; the core's per-vertex normals become custom split normals only when asked (they
    cost a loop-normal pass and auto smooth on every later evaluation). `edges`: the pair
    ifsforge.mesh_edges returns for these faces (else Blender computes them)."""
    positions = np.ascontiguousarray(positions, np.float32).reshape(-1, 3)
    faces = np.asarray(faces)
    # Index arrays are uint32: Blender 3.4's foreach_set copies them in bulk only in that format
    # (int32 goes element by element, far slower).
    faces = np.ascontiguousarray(faces, np.uint32).reshape(len(faces), -1)
    count, size = faces.shape
    mesh.clear_geometry()
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    if edges is not None:
        mesh.edges.add(len(edges[0]))
        mesh.edges.foreach_set("vertices", edges[0].ravel())
    mesh.loops.add(faces.size)
    mesh.loops.foreach_set("vertex_index", faces.ravel())
    if edges is not None:
        mesh.loops.foreach_set("edge_index", edges[1])
    mesh.polygons.add(count)
    mesh.polygons.foreach_set("loop_start", np.arange(0, faces.size, size, dtype=np.uint32))
    mesh.polygons.foreach_set("loop_total", np.full(count, size, np.uint32))
    if smooth:
        mesh.polygons.foreach_set("use_smooth", np.ones(count, bool))
    if uvs is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", np.ascontiguousarray(uvs, np.float32)[faces.ravel()].ravel())
    if colors is not None:
        set_colors(mesh, color_name, colors)
    mesh.update(calc_edges=edges is None)
    if custom_normals and normals is not None and len(normals) == len(positions):
        mesh.use_auto_smooth = True
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(normals, np.float32).reshape(-1, 3))


def linear_colors(colors):
    """(n, 4) float32 linear RGBA from display (sRGB) RGB(A) in [0, 1]: the one colour rule,
    through the core's srgb_to_linear; alpha is not encoded."""
    colors = np.asarray(colors, np.float32)
    out = np.ones((len(colors), 4), np.float32)
    out[:, :3] = ifsforge.srgb_to_linear(colors[:, :3])
    if colors.shape[1] == 4:
        out[:, 3] = colors[:, 3]
    return out


def set_colors(mesh, name, colors):
    """A per-vertex FLOAT_COLOR attribute (linear, as Blender stores it) from display RGB(A)."""
    if name in mesh.attributes:
        mesh.attributes.remove(mesh.attributes[name])
    attribute = mesh.attributes.new(name, 'FLOAT_COLOR', 'POINT')
    attribute.data.foreach_set("color", linear_colors(colors).ravel())


def center(lo, hi, base=False):
    """The point of the box (lo, hi) where a generated object's origin goes: its center (pivot
    where artists expect it), or with base=True the center of its bottom face (a terrain stands
    on the 3D cursor)."""
    middle = (np.asarray(lo, np.float64) + np.asarray(hi, np.float64)) / 2
    if base:
        middle[2] = lo[2]
    return tuple(float(v) + 0.0 for v in middle)


def points_mesh(mesh, positions):
    """Replaces `mesh`'s geometry by loose vertices."""
    positions = np.ascontiguousarray(positions, np.float32).reshape(-1, 3)
    mesh.clear_geometry()
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.update()


def set_attribute(mesh, name, kind, values):
    """A per-vertex attribute of type `kind` ('FLOAT', 'INT', 'FLOAT_VECTOR')."""
    if name in mesh.attributes:
        mesh.attributes.remove(mesh.attributes[name])
    attribute = mesh.attributes.new(name, kind, 'POINT')
    field = "vector" if kind == 'FLOAT_VECTOR' else "value"
    dtype = np.int32 if kind == 'INT' else np.float32
    attribute.data.foreach_set(field, np.ascontiguousarray(values, dtype).ravel())
