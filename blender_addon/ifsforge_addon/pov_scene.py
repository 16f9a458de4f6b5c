"""The scene's ifsforge objects as one POV-Ray 3.7 scene, seen through Blender's active camera and
lit by its sun and point lights. Terrains and iso-surfaces become mesh2 with their per-vertex
colours (the palette or the iso-surface's colours); an instances object becomes one union of its
prototypes, each declared once as a mesh2 and placed by its instance matrix; a volume becomes
absorbing and emitting media in a box, reading its density from a .df3 beside the scene
(ifsforge.write_df3, rendered again from the object's stored values).

Axes: Blender is right-handed with z up; POV-Ray is left-handed with y up. Swapping y and z maps
one onto the other (a reflection, which is exactly the change of handedness), so every point,
direction and matrix column goes through swap_yz and nothing else."""
import io
import math
import os

import numpy as np

import ifsforge

SWAP = np.array([[1, 0, 0], [0, 0, 1], [0, 1, 0]], np.float64)  # Blender (x, y, z) -> POV-Ray (x, z, y)


def swap_yz(v):
    return np.asarray(v, np.float64) @ SWAP.T


def vec(v):
    return "<%.7g, %.7g, %.7g>" % tuple(float(x) for x in v)


def rows(values, fmt):
    """Lines "fmt," for every row (numpy formats them, no per-element Python)."""
    out = io.StringIO()
    np.savetxt(out, np.asarray(values), fmt=fmt + ",")
    return out.getvalue()


def camera(obj, width, height):
    """POV-Ray camera of a Blender perspective camera: location, orthonormal right/up/direction
    from its world matrix (Blender cameras look along their -z, up their +y), the field of view
    across the wider side as Blender's 'Auto' sensor fit does."""
    m = np.array(obj.matrix_world, np.float64)
    axes = m[:3, :3] / np.linalg.norm(m[:3, :3], axis=0)  # without the object's scale
    right, up, forward = swap_yz(axes[:, 0]), swap_yz(axes[:, 1]), swap_yz(-axes[:, 2])
    aspect = width / height
    data = obj.data
    if data.type != 'PERSP':
        raise ifsforge.InputError(f"camera '{obj.name}': only perspective cameras are exported")
    half = math.tan(data.angle / 2)  # the wider side's half-width at distance 1 (sensor fit Auto)
    right_len, up_len = aspect, 1.0
    direction = forward * (max(aspect, 1.0) / 2 / half)
    location = swap_yz(m[:3, 3])
    return (f"camera {{\n  perspective\n  location {vec(location)}\n  right {vec(right * right_len)}\n"
            f"  up {vec(up * up_len)}\n  direction {vec(direction)}\n}}\n")


def light(obj):
    """A sun as a parallel light from far along its -z; a point light where it is."""
    m = np.array(obj.matrix_world, np.float64)
    color = np.array(obj.data.color) * min(obj.data.energy if obj.data.type == 'SUN' else 1.0, 2.0)
    if obj.data.type == 'SUN':
        towards = swap_yz(-m[:3, 2] / np.linalg.norm(m[:3, 2]))
        return (f"light_source {{ {vec(-towards * 1e5)} color rgb {vec(color)} parallel "
                f"point_at <0, 0, 0> }}\n")
    if obj.data.type == 'POINT':
        return f"light_source {{ {vec(swap_yz(m[:3, 3]))} color rgb {vec(color)} }}\n"
    return ""


def mesh_arrays(mesh, matrix=None):
    """(positions (n, 3) in POV-Ray axes, triangles (m, 3), colours (n, 3) or None) of a mesh."""
    mesh.calc_loop_triangles()
    co = np.zeros(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(np.float64)
    if matrix is not None:
        m = np.array(matrix, np.float64)
        co = co @ m[:3, :3].T + m[:3, 3]
    tris = np.zeros(len(mesh.loop_triangles) * 3, np.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    colors = None
    for attribute in mesh.color_attributes:
        if attribute.domain == 'POINT' and len(attribute.data) == len(mesh.vertices):
            values = np.zeros(len(mesh.vertices) * 4, np.float32)
            attribute.data.foreach_get("color_srgb", values)
            colors = values.reshape(-1, 4)[:, :3]
            break
    return swap_yz(co), tris.reshape(-1, 3), colors


def mesh2(name, positions, triangles, colors=None, color=(0.8, 0.8, 0.8)):
    """A mesh2; the triangles' winding is reversed with the handedness so the faces keep facing out."""
    text = [f"mesh2 {{ // {ifsforge.pov_comment(name)}\n  vertex_vectors {{ {len(positions)},\n",
            rows(positions, "    <%.7g, %.7g, %.7g>"), "  }\n"]
    faces = triangles[:, ::-1]
    if colors is not None:
        text += [f"  texture_list {{ {len(colors)},\n",
                 rows(colors, "    texture { pigment { rgb <%.4g, %.4g, %.4g> } }"), "  }\n",
                 f"  face_indices {{ {len(faces)},\n", rows(np.hstack([faces, faces]), "    <%d, %d, %d>, %d, %d, %d"),
                 "  }\n}\n"]
    else:
        text += [f"  face_indices {{ {len(faces)},\n", rows(faces, "    <%d, %d, %d>"), "  }\n",
                 f"  texture {{ pigment {{ rgb {vec(color)} }} }}\n}}\n"]
    return "".join(text)


def volume_media(obj, path):
    """A box over the volume's grid holding media whose density is the .df3 written beside `path`;
    the unit cube POV-Ray maps the file onto goes to the grid's box, then to the object's place."""
    from . import generators, properties, state
    from .generate_volume import render_volume
    values = properties.snapshot(obj.ifsforge.system, obj.ifsforge.settings)["settings"]
    volume = render_volume(state.system_of(obj.ifsforge.system), generators.get('VOLUME').resolve(dict(values)), None)
    df3 = f"{os.path.splitext(path)[0]}_{ifsforge.pov_name(obj.name)}.df3"
    ifsforge.write_df3(df3, volume, bits=8)
    grid = np.diag([*(np.array(volume.dims, np.float64) * volume.voxel_size), 1.0])
    grid[:3, 3] = volume.origin
    m = np.array(obj.matrix_world, np.float64) @ grid
    p, t = SWAP @ m[:3, :3], swap_yz(m[:3, 3])  # file axes are the volume's own x, y, z
    values = ", ".join("%.7g" % v for v in [*p[:, 0], *p[:, 1], *p[:, 2], *t])
    strength = obj.ifsforge.settings.volume_strength
    return (f"box {{ 0, 1 // {ifsforge.pov_comment(obj.name)}\n  pigment {{ rgbt 1 }} hollow\n"
            f"  interior {{ media {{ absorption {2 * strength:.6g} emission 0.3 method 3 intervals 1 samples 8\n"
            f"    density {{ density_file df3 {ifsforge.pov_string(os.path.basename(df3))} interpolate 1 }} }} }}\n"
            f"  matrix <{values}>\n}}\n")


def write_scene(path, context, width, height):
    """Writes the scene; returns {kind: count} of the objects written."""
    scene = context.scene
    if scene.camera is None:
        raise ifsforge.InputError("the scene has no active camera to export")
    depsgraph = context.evaluated_depsgraph_get()
    parts = [f"// {ifsforge.pov_comment(scene.name)}: ifsforge objects exported from Blender\n",
             "#version 3.7;\nglobal_settings { assumed_gamma 1.0 ambient_light rgb 1 }\n",
             "background { rgb <1, 0, 1> }\n", camera(scene.camera, width, height)]
    lights = [light(obj) for obj in scene.objects if obj.type == 'LIGHT' and obj.visible_get()]
    parts += [text for text in lights if text] or ["light_source { <1e4, 2e4, -1e4> color rgb 1 }\n"]
    parts.append("#default { finish { ambient 0.15 diffuse 0.85 } }\n")
    counts, prototypes, placements = {}, {}, {}
    for inst in depsgraph.object_instances:
        if inst.is_instance:
            parent = inst.parent.original if inst.parent else None
            if parent is None or parent.ifsforge.kind != 'INSTANCES' or inst.object.type != 'MESH':
                continue
            source = inst.object.original
            if source.name not in prototypes:
                mesh = inst.object.to_mesh()
                prototypes[source.name] = mesh_arrays(mesh)
                inst.object.to_mesh_clear()
            placements.setdefault(parent.name, []).append((source.name, np.array(inst.matrix_world)))
            continue
        obj = inst.object.original
        if obj.type == 'MESH' and obj.ifsforge.kind in ('TERRAIN', 'MESH'):
            mesh = inst.object.to_mesh()
            positions, triangles, colors = mesh_arrays(mesh, inst.object.matrix_world)
            inst.object.to_mesh_clear()
            parts.append(mesh2(obj.name, positions, triangles, colors))
            counts[obj.ifsforge.kind] = counts.get(obj.ifsforge.kind, 0) + 1
        elif obj.type == 'VOLUME' and obj.ifsforge.kind == 'VOLUME':
            parts.append(volume_media(obj, path))
            counts['VOLUME'] = counts.get('VOLUME', 0) + 1
    names = {name: ifsforge.pov_identifier("Prototype", name) for name in prototypes}
    for name, (positions, triangles, colors) in prototypes.items():
        parts.append(f"#declare {names[name]} = " + mesh2(name, positions, triangles, colors))
    for parent, placed in placements.items():
        parts.append(f"union {{ // {ifsforge.pov_comment(parent)}: {len(placed)} instances\n")
        for name, m in placed:
            # POV-Ray's matrix: rows are the images of x, y, z, then the translation (row vectors).
            p = SWAP @ m[:3, :3] @ SWAP.T
            t = swap_yz(m[:3, 3])
            values = ", ".join("%.7g" % v for v in [*p[:, 0], *p[:, 1], *p[:, 2], *t])
            parts.append(f"  object {{ {names[name]} matrix <{values}> }}\n")
        parts.append("}\n")
        counts['INSTANCES'] = counts.get('INSTANCES', 0) + 1
    if not counts:
        raise ifsforge.InputError("the scene has no terrain, iso-surface, instances or volume object to export")
    text = "".join(parts)
    tmp = f"{path}.tmp"
    with open(tmp, "w", encoding="utf-8") as handle:
        handle.write(text)
    os.replace(tmp, path)
    return counts
