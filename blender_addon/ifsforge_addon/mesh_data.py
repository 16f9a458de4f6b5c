"""Arrays from the ifsforge module into Blender meshes (bulk foreach_set, no per-element Python)."""
import numpy as np

import ifsforge


def fill_mesh(mesh, positions, triangles, normals=None, uvs=None, colors=None, color_name="ifs_color",
              smooth=True):
    """Replaces `mesh`'s geometry by triangles over positions; optional per-vertex normals (custom
    split normals), uvs (per vertex, as the layer "UVMap") and display RGB(A) colours (a colour
    attribute, stored linear)."""
    positions = np.ascontiguousarray(positions, np.float32).reshape(-1, 3)
    triangles = np.ascontiguousarray(triangles, np.int32).reshape(-1, 3)
    mesh.clear_geometry()
    mesh.vertices.add(len(positions))
    mesh.vertices.foreach_set("co", positions.ravel())
    mesh.loops.add(3 * len(triangles))
    mesh.loops.foreach_set("vertex_index", triangles.ravel())
    mesh.polygons.add(len(triangles))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(triangles), 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(triangles), 3, np.int32))
    mesh.polygons.foreach_set("use_smooth", np.full(len(triangles), smooth, bool))
    if uvs is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        layer.data.foreach_set("uv", np.ascontiguousarray(uvs, np.float32)[triangles.ravel()].ravel())
    if colors is not None:
        set_colors(mesh, color_name, colors)
    mesh.update()
    mesh.validate()
    if normals is not None and len(normals) == len(positions):
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
