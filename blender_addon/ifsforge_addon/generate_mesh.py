"""The iso-surface of the system's volume (seed chapter 7: voxels have no normals, an
iso-surface gives ray tracers a surface): ifsforge.volume_to_mesh, as a mesh object whose
material reads the per-vertex colour ("ifs_color") when the layout has colour."""
import bpy
import numpy as np

import ifsforge

from . import mesh_data
from .generate_volume import render_volume
from .generators import Generator, link_object, node_material, register_generator


class MeshGenerator(Generator):
    kind = 'MESH'
    label = "Iso-surface"
    suffix = ""  # the mesh lives in the .blend

    needs = ("render_volume", "volume_to_mesh", "srgb_to_linear")
    feature = "iso-surfaces"
    default_sample = "sierpinski_tetrahedron.json"  # light: a Menger sponge is 6 M triangles at 256

    def draw(self, layout, settings, system):
        layout.prop(settings, "volume_resolution")
        layout.prop(settings, "volume_algorithm")
        layout.prop(settings, "mesh_iso")
        layout.prop(settings, "mesh_adaptivity")
        layout.prop(settings, "custom_normals")

    def work(self, system, settings, path, progress):
        if system.spatial_dims != 3:
            raise ifsforge.InputError(f"'{system.name}' is planar ({system.layout}): iso-surfaces need an xyz layout")
        volume = render_volume(system, dict(settings, volume_density="binary"),
                               lambda fraction: progress(0.5 * fraction))
        # The core's normals serve only as custom normals: smooth shading derives its own.
        mesh = mesh_data.prepare(ifsforge.volume_to_mesh(volume, iso=settings["mesh_iso"],
                                                            adaptivity=settings["mesh_adaptivity"],
                                                            normals=settings["custom_normals"],
                                                            progress=lambda fraction: progress(0.5 + 0.5 * fraction)))
        positions = np.asarray(mesh["positions"], np.float64)
        origin = mesh_data.center(positions.min(axis=0), positions.max(axis=0)) if len(positions) else (0.0,) * 3
        mesh["positions"] = positions - origin
        return {"path": None, "mesh": mesh, "custom_normals": settings["custom_normals"], "origin": origin,
                "summary": f"{len(mesh['positions']):,} vertices, {len(mesh['triangles']):,} triangles from "
                           f"{len(volume):,} voxels"}

    def apply(self, context, owner, result, name):
        if owner is None:
            owner = bpy.data.objects.new(name, bpy.data.meshes.new(name))
            link_object(context, owner)
        data = result["mesh"]
        mesh_data.fill_mesh(owner.data, data["positions"], data["faces"], normals=data["normals"],
                            colors=data["colors"], edges=data["edges"], custom_normals=result["custom_normals"])
        owner.data.materials.clear()
        owner.data.materials.append(material(name, data["colors"] is not None))
        return owner


def material(name, coloured):
    mat, nodes, links = node_material(name)
    shader = nodes.new('ShaderNodeBsdfPrincipled')
    output = nodes.new('ShaderNodeOutputMaterial')
    links.new(shader.outputs["BSDF"], output.inputs["Surface"])
    if coloured:
        attribute = nodes.new('ShaderNodeAttribute')
        attribute.attribute_type, attribute.attribute_name = 'GEOMETRY', "ifs_color"
        links.new(attribute.outputs["Color"], shader.inputs["Base Color"])
        attribute.location = (-300, 0)
    output.location = (300, 0)
    return mat


register_generator(MeshGenerator())
