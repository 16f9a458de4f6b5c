"""The scene's ifsforge objects as one POV-Ray 3.7 scene that renders as Cycles does: seen through
Blender's active camera, lit by its sun and point lights and by the world colour, which is also
the background. Terrains and iso-surfaces become mesh2 with their per-vertex colours; an instances
object becomes one union of its prototypes, each declared once as a mesh2 and placed by its
instance matrix with its own colour ("ifs_color"); a volume becomes media in a box reading its
density and its colour from .df3 files beside the scene (ifsforge.write_df3, rendered again from
the object's stored values), with the Principled Volume's density, colour and emission.

Colours: every value is written as what POV-Ray reads under assumed_gamma 1.0: display colours
(colour attributes' sRGB values) as srgb, Blender's scene-linear values (node defaults, lights,
world) as rgb. Light units: Cycles' diffuse radiance is albedo * E / pi for an irradiance E, POV-Ray's
is pigment * light colour, so a sun of strength S becomes a light of S / pi, a point light of P watts
one of P / (8 pi^2) with POV-Ray's fade (2 / (1 + d^2) for d >> 1: P / (4 pi d^2) / pi). The world's
uniform light is POV-Ray's ambient light (finish ambient 1), without Cycles' occlusion.

Axes: Blender is right-handed with z up; POV-Ray is left-handed with y up. Swapping y and z maps
one onto the other (a reflection, which is exactly the change of handedness), so every point,
direction and matrix column goes through swap_yz and nothing else."""
import io
import math
import os

import numpy as np

import ifsforge
from ifsforge import media

SWAP = np.array([[1, 0, 0], [0, 0, 1], [0, 1, 0]], np.float64)  # Blender (x, y, z) -> POV-Ray (x, z, y)
GRAY = (0.8, 0.8, 0.8)  # Principled BSDF's default base colour (linear)


def swap_yz(v):
    return np.asarray(v, np.float64) @ SWAP.T


def vec(v, digits=7):
    return "<" + ", ".join("%.*g" % (digits, float(x)) for x in v) + ">"


def rows(values, fmt):
    """Lines "fmt," for every row (numpy formats them, no per-element Python)."""
    out = io.StringIO()
    np.savetxt(out, np.asarray(values), fmt=fmt + ",")
    return out.getvalue()


def unit(v):
    return v / np.linalg.norm(v)


def camera(obj, width, height):
    """POV-Ray camera of a Blender camera: location and exactly perpendicular right, up and
    direction (Gram-Schmidt of its world matrix's axes, written with every digit, so POV-Ray
    finds them perpendicular); Blender cameras look along their -z, up their +y. The field of
    view (or orthographic scale) spans the wider side, as Blender's 'Auto' sensor fit does."""
    m = np.array(obj.matrix_world, np.float64)
    right = unit(swap_yz(m[:3, 0]))
    up = unit(swap_yz(m[:3, 1]) - right * np.dot(right, unit(swap_yz(m[:3, 1]))))
    forward = np.cross(right, up)  # left-handed axes: right x up = direction
    aspect = width / height
    data = obj.data
    location = swap_yz(m[:3, 3])
    if data.type == 'PERSP':
        half = math.tan(data.angle / 2)  # the wider side's half-width at distance 1 (sensor fit Auto)
        kind, right, up, direction = "perspective", right * aspect, up, forward * (max(aspect, 1.0) / 2 / half)
    elif data.type == 'ORTHO':
        scale = data.ortho_scale  # the wider side's extent
        kind, right, up, direction = ("orthographic", right * scale * min(aspect, 1.0),
                                      up * scale / max(aspect, 1.0), forward)
    else:
        raise ifsforge.InputError(f"camera '{obj.name}': only perspective and orthographic cameras are exported")
    return (f"camera {{\n  {kind}\n  location {vec(location, 17)}\n  right {vec(right, 17)}\n"
            f"  up {vec(up, 17)}\n  direction {vec(direction, 17)}\n}}\n")


def light(obj):
    """A sun as a parallel light from far along its -z; a point light where it is (see the units
    above). Both shine through media, attenuated, so volumes cast shadows as in Cycles."""
    m = np.array(obj.matrix_world, np.float64)
    color = np.array(obj.data.color, np.float64)
    if obj.data.type == 'SUN':
        towards = swap_yz(-m[:3, 2] / np.linalg.norm(m[:3, 2]))
        return (f"light_source {{ {vec(-towards * 1e5)} color rgb {vec(color * obj.data.energy / math.pi)} "
                f"parallel point_at <0, 0, 0> media_attenuation on }}\n")
    if obj.data.type == 'POINT':
        return (f"light_source {{ {vec(swap_yz(m[:3, 3]))} color rgb {vec(color * obj.data.energy / (8 * math.pi ** 2))} "
                f"fade_distance 1 fade_power 2 media_attenuation on }}\n")
    return ""


def world_color(scene):
    """The world's linear colour: its Background node's colour times strength (the default
    value when a texture drives it), else the world's viewport colour."""
    world = scene.world
    if world is None:
        return np.zeros(3)
    if world.use_nodes and world.node_tree:
        for node in world.node_tree.nodes:
            if node.type == 'BACKGROUND':
                return np.array(node.inputs["Color"].default_value[:3]) * node.inputs["Strength"].default_value
    return np.array(world.color[:3], np.float64)


def principled(obj, kind):
    """The first node of type `kind` in the object's first material, or None."""
    mat = obj.active_material
    if mat is None or not mat.use_nodes:
        return None
    return next((node for node in mat.node_tree.nodes if node.type == kind), None)


def base_color(obj):
    """(linear RGB, the colour attribute the material reads or None) of a Principled BSDF."""
    shader = principled(obj, 'BSDF_PRINCIPLED')
    if shader is None:
        return GRAY, None
    socket = shader.inputs["Base Color"]
    attribute = None
    if socket.is_linked and socket.links[0].from_node.type == 'ATTRIBUTE':
        attribute = socket.links[0].from_node.attribute_name
    return tuple(socket.default_value[:3]), attribute


def point_colors(mesh, name=None):
    """The display (sRGB) RGBA of a per-vertex colour attribute: `name`, else the first one."""
    for attribute in mesh.color_attributes:
        if (name is None or attribute.name == name) and attribute.domain == 'POINT':
            values = np.zeros(len(attribute.data) * 4, np.float32)
            attribute.data.foreach_get("color_srgb", values)
            return values.reshape(-1, 4)
    return None if name is None else point_colors(mesh)


def mesh_arrays(mesh, matrix=None, color_name=None):
    """(positions (n, 3) in POV-Ray axes, triangles (m, 3), display colours (n, 3) or None,
    vertex normals (n, 3) in POV-Ray axes where the mesh is smooth-shaded, else None)."""
    mesh.calc_loop_triangles()
    co = np.zeros(len(mesh.vertices) * 3, np.float32)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3).astype(np.float64)
    smooth = np.zeros(len(mesh.polygons), bool)
    mesh.polygons.foreach_get("use_smooth", smooth)
    normals = None
    if smooth.any():
        normals = np.zeros(len(mesh.vertices) * 3, np.float32)
        mesh.vertices.foreach_get("normal", normals)
        normals = normals.reshape(-1, 3).astype(np.float64)
    if matrix is not None:
        m = np.array(matrix, np.float64)
        co = co @ m[:3, :3].T + m[:3, 3]
        if normals is not None:
            normals = normals @ np.linalg.inv(m[:3, :3])  # by the inverse transpose
    if normals is not None:
        length = np.linalg.norm(normals, axis=1, keepdims=True)
        normals = swap_yz(np.divide(normals, length, out=np.zeros_like(normals), where=length > 0))
    tris = np.zeros(len(mesh.loop_triangles) * 3, np.int64)
    mesh.loop_triangles.foreach_get("vertices", tris)
    colors = point_colors(mesh, color_name)
    if colors is not None and len(colors) != len(mesh.vertices):
        colors = None
    return swap_yz(co), tris.reshape(-1, 3), None if colors is None else colors[:, :3], normals


def mesh2(name, positions, triangles, colors=None, color=None, normals=None):
    """A mesh2 with per-vertex display colours (srgb), one linear colour (rgb), or no texture (the
    object placing it gives one), smooth with per-vertex normals; the winding is reversed with the
    handedness so the faces keep facing out."""
    text = [f"mesh2 {{ // {ifsforge.pov_comment(name)}\n  vertex_vectors {{ {len(positions)},\n",
            rows(positions, "    <%.7g, %.7g, %.7g>"), "  }\n"]
    if normals is not None:  # indexed as the vertices (no normal_indices)
        text += [f"  normal_vectors {{ {len(normals)},\n", rows(normals, "    <%.5f, %.5f, %.5f>"), "  }\n"]
    faces = triangles[:, ::-1]
    if colors is not None:
        text += [f"  texture_list {{ {len(colors)},\n",
                 rows(colors, "    texture { pigment { srgb <%.4f, %.4f, %.4f> } }"), "  }\n",
                 f"  face_indices {{ {len(faces)},\n", rows(np.hstack([faces, faces]), "    <%d, %d, %d>, %d, %d, %d"),
                 "  }\n}\n"]
    else:
        text += [f"  face_indices {{ {len(faces)},\n", rows(faces, "    <%d, %d, %d>"), "  }\n"]
        if color is not None:
            text.append(f"  texture {{ pigment {{ rgb {vec(color)} }} }}\n")
        text.append("}\n")
    return "".join(text)


def instances_union(parent, placed, names, colors):
    """One union of an instances object's placements [(prototype, matrix, point index)], each
    with its point's display colour (srgb; srgbt where it is not opaque) when there are colours."""
    lines = [f"union {{ // {ifsforge.pov_comment(parent)}: {len(placed)} instances\n"]
    for name in sorted({p[0] for p in placed}):
        chosen = [p for p in placed if p[0] == name]
        m = np.array([p[1] for p in chosen], np.float64)
        # POV-Ray's matrix: rows are the images of x, y, z, then the translation (row vectors).
        linear = np.einsum("ij,njk,lk->nil", SWAP, m[:, :3, :3], SWAP)
        values = np.hstack([linear.transpose(0, 2, 1).reshape(-1, 9), swap_yz(m[:, :3, 3])])
        fmt = f"  object {{ {names[name]} matrix <" + ", ".join(["%.7g"] * 12) + ">"
        if colors is None:
            lines.append(rows(values, fmt + " }").replace(",\n", "\n"))
            continue
        rgba = colors[[p[2] for p in chosen]]
        opaque = rgba[:, 3] >= 0.9995
        for keep, pigment in ((opaque, " pigment { srgb <%.4f, %.4f, %.4f> } }"),
                              (~opaque, " pigment { srgbt <%.4f, %.4f, %.4f, %.4f> } }")):
            if keep.any():
                columns = rgba[keep][:, :3] if pigment.count("%") == 3 else \
                    np.hstack([rgba[keep][:, :3], 1.0 - rgba[keep][:, 3:]])
                lines.append(rows(np.hstack([values[keep], columns]), fmt + pigment).replace(",\n", "\n"))
    lines.append("}\n")
    return "".join(lines)


def linked(socket):
    """The node feeding `socket`, or None."""
    return socket.links[0].from_node if socket.is_linked else None


def volume_settings(obj, volume):
    """What the object's Principled Volume makes of its grids, as Cycles reads it: (density scale,
    linear Color, whether the "color" grid multiplies it, emission). Emission is (constant
    linear RGB, per-density factor, colour or None for the "color" grid): the factor is set where
    Emission Strength is the "density" attribute times a number (the add-on's colour volumes),
    else the constant is emitted wherever the grid has voxels."""
    shader = principled(obj, 'PRINCIPLED_VOLUME')
    if shader is None:  # no add-on material: the density it would have given, per world unit
        return (obj.ifsforge.settings.volume_strength * media.per_world_unit(volume), np.full(3, 0.5), False,
                (np.zeros(3), 0.0, None))
    inputs = shader.inputs
    source = linked(inputs["Emission Color"])
    emission_color = (None if source is not None and source.type == 'ATTRIBUTE' and source.attribute_name == "color"
                      else np.array(inputs["Emission Color"].default_value[:3], np.float64))
    strength, per_density = inputs["Emission Strength"].default_value, 0.0
    scale = linked(inputs["Emission Strength"])
    if scale is not None:
        strength = 0.0
        if scale.type == 'MATH' and scale.operation == 'MULTIPLY':
            feeds = [linked(socket) for socket in scale.inputs[:2]]
            for k in range(2):
                if feeds[k] is not None and feeds[k].type == 'ATTRIBUTE' and feeds[k].attribute_name == "density" \
                        and feeds[1 - k] is None:
                    per_density = scale.inputs[1 - k].default_value
    constant = np.zeros(3) if emission_color is None else emission_color * strength
    return (inputs["Density"].default_value, np.array(inputs["Color"].default_value[:3], np.float64),
            inputs["Color Attribute"].default_value == "color", (constant, per_density, emission_color))


def df3_density(name, interpolate=1, color_map=None):
    return (f"density_file df3 {ifsforge.pov_string(name)} interpolate {interpolate}"
            + (f" color_map {{ {color_map} }}" if color_map else ""))


def grid_matrix(obj, volume):
    """Blender's voxel index -> object space of the evaluated volume (the file's transform, which
    centres the grid's box on the object's origin, and any modifiers), else the grid's own
    placement moved by that centre; voxel i spans [i, i + 1] of index space."""
    import bpy
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    grid = evaluated.grids.get("density") if evaluated.grids.is_loaded else None
    if grid is not None:
        return np.array(grid.matrix_object, np.float64)
    m = np.diag([volume.voxel_size] * 3 + [1.0])
    m[:3, 3] = np.asarray(volume.origin, np.float64) - np.asarray(obj.ifsforge.origin, np.float64)
    return m


def volume_media(obj, path, world):
    """A box over the volume's grid holding Principled Volume's media: scattering of albedo
    `color` and absorption of 1 - color, their sum the extinction density * grid density (as
    Cycles); the world's light scattered in as emission (the sun's is POV-Ray's scattering,
    whose isotropic phase is 1 where Cycles' is 1 / (4 pi): a quarter of the coefficient with
    extinction 4 for the same extinction, lights already divided by pi), and the shader's own
    emission. The colour comes from a .df3 per linear channel, averaged into an RGB density.
    The files have an empty border (write_df3's border: POV-Ray's interpolation wraps round
    and puts file voxel j at j / (n + 2) of the unit cube, voxel j - 1 of the grid); the unit
    cube goes to Blender's voxel index space, then to the object and the world."""
    from . import generators, properties, state
    from .generate_volume import render_volume
    values = properties.snapshot(obj.ifsforge.system, obj.ifsforge.settings)["settings"]
    volume = render_volume(state.system_of(obj.ifsforge.system), generators.get('VOLUME').resolve(dict(values)), None)
    stem = f"{os.path.splitext(path)[0]}_{ifsforge.pov_name(obj.name)}"
    ifsforge.write_df3(f"{stem}.df3", volume, bits=16, border=True)
    strength, base, by_grid, (constant, per_density, emission_color) = volume_settings(obj, volume)
    top = float(np.max(volume.density)) if len(volume) else 0.0  # the .df3 holds density / top
    sigma = strength * top
    density = f"density {{ {df3_density(os.path.basename(stem) + '.df3')} }}"
    by_grid = by_grid and volume.color is not None
    glows = per_density > 0 and emission_color is None and volume.color is not None
    if by_grid or glows:
        maps = []
        for channel, axis in zip(media.CHANNELS, ("<3, 0, 0>", "<0, 3, 0>", "<0, 0, 3>")):
            name = media.channel_path(f"{stem}.df3", channel)
            ifsforge.write_df3(name, volume, bits=16, content=channel, border=True)
            maps.append((os.path.basename(name), axis))

    def tint(reverse=False):
        """The colour grid c (or 1 - c) as an RGB density: three channels averaged, each x 3."""
        entries = "".join(
            f"      [1 {df3_density(name, color_map=f'[0 rgb {axis}] [1 rgb 0]' if reverse else f'[0 rgb 0] [1 rgb {axis}]')}]\n"
            for name, axis in maps)
        return "density { average density_map {\n" + entries + "    } }"

    def medium(comment, body, *densities):
        return (f"    media {{ // {comment}\n      method 3 intervals 1 samples {media.MEDIA_SAMPLES}\n      {body}\n"
                + "".join(f"      {d}\n" for d in densities) + "    }\n")

    # Cycles: scattering Color x c x density, absorption (1 - Color x c) x density.
    glow_here = glows and by_grid  # the colour's emission rides on the scattering medium's c
    interior = [medium("scattering: the lights, and the world as emission",
                    f"scattering {{ 1, rgb {vec(base * sigma / 4)} extinction 4 }}\n      emission rgb "
                    f"{vec(base * sigma * np.asarray(world) + (per_density * top if glow_here else 0.0))}",
                    density, *([tint()] if by_grid else []))]
    if (1.0 - base).max() > 0:
        interior.append(medium("absorption", f"absorption rgb {vec((1.0 - base) * sigma)}", density))
    if by_grid:
        interior.append(medium("absorption of what the colour does not scatter",
                            f"absorption rgb {vec(base * sigma)}", density, tint(reverse=True)))
    if glows and not by_grid:
        interior.append(medium("emission of the colour", f"emission rgb {vec(np.full(3, per_density * top))}",
                            density, tint()))
    if per_density > 0 and emission_color is not None:
        interior.append(medium("emission", f"emission rgb {vec(emission_color * per_density * top)}", density))
    if constant.max() > 0:  # a constant emission, where the grid has voxels
        occupied = df3_density(os.path.basename(stem) + '.df3', 1, '[0 rgb 0] [0.00001 rgb 1] [1 rgb 1]')
        interior.append(medium("emission", f"emission rgb {vec(constant)}", f"density {{ {occupied} }}"))
    unit = np.diag([*(np.array(volume.dims, np.float64) + 2), 1.0])
    unit[:3, 3] = -0.5  # file voxel j: grid voxel j - 1, whose centre is at index j - 1/2
    m = np.array(obj.matrix_world, np.float64) @ grid_matrix(obj, volume) @ unit
    p, t = SWAP @ m[:3, :3], swap_yz(m[:3, 3])  # file axes are the volume's own x, y, z
    values = ", ".join("%.7g" % v for v in [*p[:, 0], *p[:, 1], *p[:, 2], *t])
    return (f"box {{ 0, 1 // {ifsforge.pov_comment(obj.name)}\n  pigment {{ rgbt 1 }} hollow\n"
            f"  interior {{\n{''.join(interior)}  }}\n  matrix <{values}>\n}}\n")


def instance_colors(owner):
    """The display RGBA "ifs_color" of every point of an instances object, or None."""
    mesh = owner.data
    colors = point_colors(mesh, "ifs_color") if "ifs_color" in mesh.attributes else None
    return colors if colors is not None and len(colors) == len(mesh.vertices) else None


def write_scene(path, context, width, height):
    """Writes the scene; returns {kind: count} of the objects written."""
    scene = context.scene
    if scene.camera is None:
        raise ifsforge.InputError("the scene has no active camera to export")
    depsgraph = context.evaluated_depsgraph_get()
    world = world_color(scene)
    parts = [f"// {ifsforge.pov_comment(scene.name)}: ifsforge objects exported from Blender\n",
             f"#version 3.7;\nglobal_settings {{ assumed_gamma 1.0 ambient_light rgb {vec(world)} }}\n",
             f"background {{ rgb {vec(world)} }}\n", camera(scene.camera, width, height)]
    lights = [light(obj) for obj in scene.objects if obj.type == 'LIGHT' and obj.visible_get() and not obj.hide_render]
    parts += [text for text in lights if text]
    parts.append("#default { finish { ambient 1 diffuse 1 } }\n")
    counts, prototypes, placements = {}, {}, {}
    for inst in depsgraph.object_instances:
        if inst.is_instance:
            parent = inst.parent.original if inst.parent else None
            if parent is None or parent.ifsforge.kind != 'INSTANCES' or inst.object.type != 'MESH' or parent.hide_render:
                continue
            source = inst.object.original
            if source.name not in prototypes:
                mesh = inst.object.to_mesh()
                prototypes[source.name] = (mesh_arrays(mesh), base_color(source)[0])
                inst.object.to_mesh_clear()
            placements.setdefault(parent.name, []).append(
                (source.name, np.array(inst.matrix_world), inst.persistent_id[0]))
            continue
        obj = inst.object.original
        if obj.hide_render:  # what Cycles renders
            continue
        if obj.type == 'MESH' and obj.ifsforge.kind in ('TERRAIN', 'MESH'):
            color, attribute = base_color(obj)
            mesh = inst.object.to_mesh()
            positions, triangles, colors, normals = mesh_arrays(mesh, inst.object.matrix_world, attribute)
            inst.object.to_mesh_clear()
            parts.append(mesh2(obj.name, positions, triangles, colors, color, normals))
            counts[obj.ifsforge.kind] = counts.get(obj.ifsforge.kind, 0) + 1
        elif obj.type == 'VOLUME' and obj.ifsforge.kind == 'VOLUME':
            parts.append(volume_media(obj, path, world))
            counts['VOLUME'] = counts.get('VOLUME', 0) + 1
    names = {name: ifsforge.pov_identifier("Prototype", name) for name in prototypes}
    colors = {parent: instance_colors(scene.objects[parent]) for parent in placements}
    for name, ((positions, triangles, vertex_colors, normals), color) in prototypes.items():
        # Coloured per instance: the prototype has no texture of its own (it would win).
        plain = all(colors[p] is not None for p, placed in placements.items() if any(n == name for n, *_ in placed))
        parts.append(f"#declare {names[name]} = " +
                     mesh2(name, positions, triangles, None if plain else vertex_colors, None if plain else color,
                           normals))
    for parent, placed in placements.items():
        parts.append(instances_union(parent, placed, names, colors[parent]))
        counts['INSTANCES'] = counts.get('INSTANCES', 0) + 1
    if not counts:
        raise ifsforge.InputError("the scene has no terrain, iso-surface, instances or volume object to export")
    ifsforge.write_bytes(path, "".join(parts).encode("utf-8"))
    return counts
