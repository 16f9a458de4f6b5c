"""Volumes (seed 6.2.3.2 binary, 6.3 gray, 6.5.3.1 RGB/HSI): ifsforge.render_volume and
write_vdb make an OpenVDB file (FloatGrid "density", Vec3fGrid "color" when the layout has
colour); Blender shows it as a Volume object whose Principled Volume reads both grids."""
import bpy
import numpy as np

import ifsforge
from ifsforge.media import per_world_unit

from . import mesh_data, outputs
from .generators import Generator, link_object, node_material, register_generator

CLIPPING = 0.001  # Blender's default: grid values below it count as empty space
# Files made before the grid was written centred carried this modifier; Regenerate removes it.
ORIGIN_MODIFIER = "ifsforge origin"


def render_volume(system, settings, progress):
    return ifsforge.render_volume(system, settings["volume_algorithm"], settings["volume_resolution"],
                                  density=settings["volume_density"], seed=settings["seed"], progress=progress)


class VolumeGenerator(Generator):
    kind = 'VOLUME'
    label = "Volume"
    suffix = ".vdb"

    needs = ("render_volume", "write_vdb")
    feature = "volumes"
    default_sample = "sierpinski_pyramid.json"

    def draw(self, layout, settings, system):
        layout.prop(settings, "volume_resolution")
        layout.prop(settings, "volume_algorithm")
        layout.prop(settings, "volume_density")
        layout.prop(settings, "volume_strength")

    def work(self, system, settings, path, progress):
        if system.spatial_dims != 3:
            raise ifsforge.InputError(f"'{system.name}' is planar ({system.layout}): volumes need an xyz layout")
        volume = render_volume(system, settings, progress)
        dims = np.asarray(volume.dims, np.float64)
        lo = np.asarray(volume.origin, np.float64)
        origin = mesh_data.center(lo, lo + dims * volume.voxel_size)
        # The file's own transform puts the grid box's centre at the object's origin: what Blender
        # reads is where it renders, with no modifier moving Blender's shared grid (which a
        # Transform node would move again at every evaluation), here or on a farm without ifsforge.
        ifsforge.write_vdb(path, volume, system, translation=[0.0 - c for c in origin])
        dims_text = "x".join(str(d) for d in volume.dims)
        values = np.asarray(volume.density, np.float32)
        return {"path": path, "voxels": len(volume), "colored": volume.color_model != "none",
                "density": settings["volume_strength"] * per_world_unit(volume),
                # Blender skips voxels below its clipping value (0.001): a measure's shares are smaller.
                "clipping": min(CLIPPING, 0.5 * float(values[values > 0].min())) if len(values) else CLIPPING,
                "origin": origin,
                "summary": f"{len(volume):,} voxels in {dims_text} ({settings['volume_algorithm']})"}

    def apply(self, context, owner, result, name):
        if owner is None:
            owner = bpy.data.objects.new(name, bpy.data.volumes.new(name))
            link_object(context, owner)
            owner.data.materials.append(material(name, result["colored"]))
        volume = owner.data
        volume.grids.unload()  # the file may have the same name: forget what was read from it
        volume.filepath = outputs.stored(result["path"])
        volume.grids.load()
        volume.update_tag()
        if not volume.grids.is_loaded:
            raise ifsforge.FileError(f"Blender could not load '{result['path']}': {volume.grids.error_message}")
        names = sorted(grid.name for grid in volume.grids)
        result["summary"] += f", grids {', '.join(names)}"
        volume.render.clipping = result["clipping"]
        set_density(owner, result["density"])
        if ORIGIN_MODIFIER in owner.modifiers:
            owner.modifiers.remove(owner.modifiers[ORIGIN_MODIFIER])
        return owner


def set_density(owner, density):
    """The add-on's material gets the density (Regenerate applies a changed Material density or
    resolution), and a colour volume's emission follows it; a material the user put instead is
    left alone."""
    for slot in owner.data.materials:
        if slot is not None and slot.node_tree is not None and slot.name.startswith(owner.name):
            nodes = slot.node_tree.nodes
            for node in nodes:
                if node.bl_idname == 'ShaderNodeVolumePrincipled':
                    node.inputs["Density"].default_value = density
            if EMISSION in nodes:
                nodes[EMISSION].inputs[1].default_value = density * GLOW


EMISSION = "ifsforge emission"  # the node scaling a colour volume's emission with its density
GLOW = 1.0  # a colour volume's emission per unit of density: where opaque it shows its colours


def material(name, coloured):
    """Principled Volume reading the "density" grid, and for a color volume the "color" grid as
    its scattering colour and as an emission proportional to the density: lit only by scattering,
    a coloured medium absorbs what it does not scatter and turns murky and dark; emitting its own
    colour where it is dense, it keeps the saturation its colours have (as the iso-surface shows
    them), at any resolution since the emission scales with the density."""
    mat, nodes, links = node_material(name)
    shader = nodes.new('ShaderNodeVolumePrincipled')
    shader.inputs["Density Attribute"].default_value = "density"
    output = nodes.new('ShaderNodeOutputMaterial')
    links.new(shader.outputs["Volume"], output.inputs["Volume"])
    output.location = (300, 0)
    if coloured:
        shader.inputs["Color Attribute"].default_value = "color"
        color, density = nodes.new('ShaderNodeAttribute'), nodes.new('ShaderNodeAttribute')
        color.attribute_name, density.attribute_name = "color", "density"
        scale = nodes.new('ShaderNodeMath')
        scale.operation, scale.name, scale.label = 'MULTIPLY', EMISSION, "Emission per density"
        links.new(density.outputs["Fac"], scale.inputs[0])
        links.new(scale.outputs[0], shader.inputs["Emission Strength"])
        links.new(color.outputs["Color"], shader.inputs["Emission Color"])
        color.location, density.location, scale.location = (-500, 100), (-500, -150), (-250, -150)
    return mat


register_generator(VolumeGenerator())
