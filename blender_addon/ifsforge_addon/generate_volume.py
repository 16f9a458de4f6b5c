"""Volumes (seed 6.2.3.2 binary, 6.3 gray, 6.5.3.1 RGB/HSI): ifsforge.render_volume and
write_vdb make an OpenVDB file (FloatGrid "density", Vec3fGrid "color" when the layout has
colour); Blender shows it as a Volume object whose Principled Volume reads both grids."""
import bpy

import ifsforge

from . import outputs
from .generators import Generator, link_object, node_material, register_generator


def render_volume(system, settings, progress):
    return ifsforge.render_volume(system, settings["volume_algorithm"], settings["volume_resolution"],
                                  density=settings["volume_density"], seed=settings["seed"], progress=progress)


class VolumeGenerator(Generator):
    kind = 'VOLUME'
    label = "Volume"
    suffix = ".vdb"

    needs = ("render_volume", "write_vdb")
    feature = "volumes"

    def draw(self, layout, settings, system):
        layout.prop(settings, "volume_resolution")
        layout.prop(settings, "volume_algorithm")
        layout.prop(settings, "volume_density")
        layout.prop(settings, "volume_strength")

    def work(self, system, settings, path, progress):
        if system.spatial_dims != 3:
            raise ifsforge.InputError(f"'{system.name}' is planar ({system.layout}): volumes need an xyz layout")
        volume = render_volume(system, settings, progress)
        ifsforge.write_vdb(path, volume, system)
        dims = "x".join(str(d) for d in volume.dims)
        return {"path": path, "voxels": len(volume), "coloured": volume.color_model != "none",
                "strength": settings["volume_strength"],
                "summary": f"{len(volume):,} voxels in {dims} ({settings['volume_algorithm']})"}

    def apply(self, context, owner, result, name):
        if owner is None:
            owner = bpy.data.objects.new(name, bpy.data.volumes.new(name))
            link_object(context, owner)
            owner.data.materials.append(material(name, result["coloured"], result["strength"]))
        volume = owner.data
        volume.grids.unload()  # the file may have the same name: forget what was read from it
        volume.filepath = outputs.stored(result["path"])
        volume.grids.load()
        volume.update_tag()
        if not volume.grids.is_loaded:
            raise ifsforge.FileError(f"Blender could not load '{result['path']}': {volume.grids.error_message}")
        names = sorted(grid.name for grid in volume.grids)
        result["summary"] += f", grids {', '.join(names)}"
        return owner


def material(name, coloured, strength):
    """Principled Volume reading the "density" grid (and "color" when there is one)."""
    mat, nodes, links = node_material(name)
    shader = nodes.new('ShaderNodeVolumePrincipled')
    shader.inputs["Density"].default_value = strength
    shader.inputs["Density Attribute"].default_value = "density"
    if coloured:
        shader.inputs["Color Attribute"].default_value = "color"
    output = nodes.new('ShaderNodeOutputMaterial')
    links.new(shader.outputs["Volume"], output.inputs["Volume"])
    output.location = (300, 0)
    return mat


register_generator(VolumeGenerator())
