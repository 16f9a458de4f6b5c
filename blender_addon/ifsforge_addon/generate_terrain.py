"""Fractal terrains (seed 6.1.3.4): control heights (sampled from the system's attractor, seeded
at random, or from a terrain recipe) interpolated by fractal interpolation along and across
the leading vectors; a mesh object whose material looks the height up in a fractal palette."""
import bpy
import numpy as np

import ifsforge

from . import mesh_data, outputs, palettes
from .generators import Generator, link_object, node_material, register_generator

ATTRACTOR_IMAGE = 256  # pixels of the density image the control heights are sampled from
IRREGULAR_SHIFT = 0.3  # an irregular grid's random displacement, in control spacings (< 0.5)
LEVEL = "ifs_level"  # the point attribute holding each vertex's normalised height


class TerrainGenerator(Generator):
    kind = 'TERRAIN'
    label = "Terrain"
    suffix = "_palette.png"

    needs = ("make_terrain", "srgb_to_linear")
    feature = "terrains"
    default_sample = "barnsley_fern.json"

    def uses_system(self, settings):
        return settings["terrain_source"] == 'ATTRACTOR'

    def draw(self, layout, settings, system):
        layout.prop(settings, "terrain_source")
        if settings.terrain_source == 'RECIPE':
            layout.prop(settings, "terrain_recipe")
            return
        layout.prop(settings, "terrain_grid")
        layout.prop(settings, "terrain_controls")
        layout.prop(settings, "terrain_roughness")
        layout.prop(settings, "terrain_resolution")
        layout.prop(settings, "terrain_size")
        layout.prop(settings, "terrain_height")
        layout.prop(settings, "palette_recipe")
        layout.prop(settings, "palette_entries")
        layout.prop(settings, "custom_normals")
        if system is not None and system.spatial_dims == 3 and settings.terrain_source == 'ATTRACTOR':
            layout.prop(settings, "view")

    def resolve(self, settings):
        settings["palette_recipe"] = palettes.recipe_path(settings)
        if settings["terrain_source"] == 'RECIPE':
            if not settings["terrain_recipe"]:
                raise ifsforge.InputError("choose a terrain recipe file (or another height source)")
            settings["terrain_recipe"] = bpy.path.abspath(settings["terrain_recipe"])
        return settings

    def work(self, system, settings, path, progress):
        if settings["terrain_source"] == 'RECIPE':
            recipe = ifsforge.read_terrain_recipe(settings["terrain_recipe"])
            controls, columns, rows = recipe.controls, recipe.columns, recipe.rows
            palette = recipe.palette.make()
        else:
            controls = self.controls(system, settings)
            columns = rows = settings["terrain_resolution"]
            palette = palettes.make(settings["palette_recipe"], settings["palette_entries"])[1]
        terrain = ifsforge.make_terrain(controls, columns, rows, progress=progress)
        mesh = terrain.mesh(palette=palette, up="z")
        low, high = terrain.min_height, terrain.max_height
        if settings["terrain_source"] != 'RECIPE':  # a recipe's heights are the recipe's
            low, high = fit_height(mesh, settings["terrain_height"])
        positions = np.asarray(mesh["positions"], np.float64)
        origin = mesh_data.center(positions.min(axis=0), positions.max(axis=0), base=True)
        mesh["positions"] = positions - origin
        if terrain.grid == "circular":  # a fan at the centre: the generic pairing and edge search
            mesh = mesh_data.prepare(mesh)
        else:  # a lattice: quads and edges known in advance (the triangles pair up along a-c)
            mesh["faces"], mesh["edges"] = mesh_data.grid_faces(terrain.columns, terrain.rows)
        ifsforge.write_png(path, palette.to_image(1), 16)
        return {"path": path, "mesh": mesh, "custom_normals": settings["custom_normals"], "origin": origin,
                "summary": f"{terrain.grid} terrain, {terrain.columns}x{terrain.rows} samples, heights "
                           f"{low:.3g} to {high:.3g}"}

    @staticmethod
    def controls(system, settings):
        """Control heights from the attractor's density image or from the seed, built by the core's
        make_terrain_controls: the CLI's `terrain` uses the same builder, so one seed gives one terrain."""
        grid, n, seed = settings["terrain_grid"], settings["terrain_controls"], settings["seed"]
        size, height = settings["terrain_size"], settings["terrain_height"]
        options = dict(grid=grid, rows=n, columns=n, size_x=size, size_y=size,
                       roughness=tuple(settings["terrain_roughness"]),
                       shift=IRREGULAR_SHIFT if grid == "irregular" else 0.0)
        if settings["terrain_source"] == 'ATTRACTOR':
            view = settings["view"] if system.spatial_dims == 3 else None
            image = ifsforge.render(system, "chaos", ATTRACTOR_IMAGE, view=view, seed=seed).to_image("density")
            options.update(height_map=image, low=0.0, high=height)
        else:
            options.update(base=0.5 * height, amplitude=0.5 * height)
        return ifsforge.make_terrain_controls(seed, **options)

    def apply(self, context, owner, result, name):
        if owner is None:
            owner = bpy.data.objects.new(name, bpy.data.meshes.new(name))
            link_object(context, owner)
        mesh, data = owner.data, result["mesh"]
        mesh_data.fill_mesh(mesh, data["positions"], data["faces"], normals=data["normals"],
                            colors=data.get("colors"), color_name="ifs_palette", edges=data["edges"],
                            custom_normals=result["custom_normals"])
        # The palette coordinate (normalised height, the core's u) per vertex: a UV layer would copy it
        # to every corner, element by element (Blender 3.4's loop uv struct is not contiguous).
        mesh_data.set_attribute(mesh, LEVEL, 'FLOAT', np.asarray(data["uvs"])[:, 0])
        mat = material(name, palette_image(f"{name} palette", result["path"]))
        mesh.materials.clear()
        mesh.materials.append(mat)
        return owner


def fit_height(mesh, height):
    """Maps the mesh's heights onto [0, height]: fractal interpolation overshoots its control
    heights (by up to about half their range at roughness 0.3), and Height is what the artist asked
    for. The normals follow the vertical scaling. Returns the new (low, high)."""
    positions = np.array(mesh["positions"], np.float64)
    low, high = positions[:, 2].min(), positions[:, 2].max()
    scale = height / (high - low) if high > low else 1.0
    positions[:, 2] = (positions[:, 2] - low) * scale
    mesh["positions"] = positions
    if mesh.get("normals") is not None and scale > 0:
        normals = np.array(mesh["normals"], np.float64)
        normals[:, 2] /= scale  # the inverse transpose of diag(1, 1, scale)
        normals /= np.maximum(np.linalg.norm(normals, axis=1, keepdims=True), 1e-12)
        mesh["normals"] = normals
    return 0.0, (high - low) * scale


def palette_image(name, path):
    image = bpy.data.images.get(name)
    if image is None:
        image = bpy.data.images.load(path, check_existing=False)
        image.name = name
    image.filepath = outputs.stored(path)
    image.reload()
    return image


def material(name, image):
    """The palette strip looked up at (normalised height, 0.5), the height read from the mesh's
    point attribute LEVEL."""
    mat, nodes, links = node_material(name)
    level = nodes.new('ShaderNodeAttribute')
    level.attribute_type, level.attribute_name = 'GEOMETRY', LEVEL
    uv = nodes.new('ShaderNodeCombineXYZ')
    uv.inputs["Y"].default_value = 0.5
    links.new(level.outputs["Fac"], uv.inputs["X"])
    texture = nodes.new('ShaderNodeTexImage')
    texture.image, texture.extension, texture.interpolation = image, 'EXTEND', 'Linear'
    shader = nodes.new('ShaderNodeBsdfPrincipled')
    shader.inputs["Roughness"].default_value = 0.9
    output = nodes.new('ShaderNodeOutputMaterial')
    links.new(uv.outputs["Vector"], texture.inputs["Vector"])
    links.new(texture.outputs["Color"], shader.inputs["Base Color"])
    links.new(shader.outputs["BSDF"], output.inputs["Surface"])
    level.location, uv.location = (-800, 0), (-600, 0)
    texture.location, shader.location, output.location = (-350, 0), (0, 0), (300, 0)
    return mat


register_generator(TerrainGenerator())
