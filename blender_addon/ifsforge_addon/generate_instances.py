"""CSG instances (vector recursive rendering, seed 5.8.2): ifsforge.instances places one
primitive per leaf; Blender shows them as instances of the primitive meshes on the points of
one object, driven by a geometry-node tree that reads each point's frame, scale, primitive
and colour. Materials read the colour with an Attribute node (type Instancer, "ifs_color")."""
import bpy

import ifsforge

from . import mesh_data
from .generators import Generator, register_generator

SEGMENTS = 24  # facets around curved primitives


class InstancesGenerator(Generator):
    kind = 'INSTANCES'
    label = "Instances"
    suffix = ""  # nothing on disk: the instance list lives in the .blend

    needs = ("instances", "srgb_to_linear")
    feature = "vector IFS"

    def draw(self, layout, settings, system):
        layout.prop(settings, "instance_depth")
        layout.prop(settings, "instance_primitives")
        layout.prop(settings, "instance_scale")
        layout.prop(settings, "instance_color_by")

    def work(self, system, settings, path, progress):
        instances = ifsforge.instances(system, depth=settings["instance_depth"],
                                       primitives=settings["instance_primitives"],
                                       scale_factor=settings["instance_scale"],
                                       color_source=settings["instance_color_by"], progress=progress)
        names = [p.name for p in instances.primitives]
        return {"path": None, "instances": instances, "meshes": [p.mesh(SEGMENTS) for p in instances.primitives],
                "names": names, "summary": f"{len(instances):,} instances of {', '.join(names)}, "
                                           f"depth {instances.addresses.depth}"}

    def apply(self, context, owner, result, name):
        instances = result["instances"]
        if owner is None:
            owner = bpy.data.objects.new(name, bpy.data.meshes.new(name))
            collection = bpy.data.collections.new(name)
            context.collection.children.link(collection)
            collection.objects.link(owner)
            context.view_layer.objects.active = owner
            owner.select_set(True)
        # One vertex per instance, with what the node tree and the material read.
        mesh = owner.data
        mesh_data.points_mesh(mesh, instances.positions)
        frames = instances.frames
        mesh_data.set_attribute(mesh, "ifs_axis_x", 'FLOAT_VECTOR', frames[:, 0, :])
        mesh_data.set_attribute(mesh, "ifs_axis_y", 'FLOAT_VECTOR', frames[:, 1, :])
        mesh_data.set_attribute(mesh, "ifs_scale", 'FLOAT', instances.scales)
        mesh_data.set_attribute(mesh, "ifs_primitive", 'INT', instances.primitive)
        mesh_data.set_colors(mesh, "ifs_color", instances.colors)
        prototypes = prototype_collection(name, result["names"], result["meshes"], material(name))
        modifier = owner.modifiers.get("ifsforge instances") or owner.modifiers.new("ifsforge instances", 'NODES')
        modifier.node_group = node_tree(name, prototypes)
        return owner


def material(name):
    """Principled BSDF whose colour and alpha are each instance's "ifs_color"."""
    mat = bpy.data.materials.get(f"{name} instances") or bpy.data.materials.new(f"{name} instances")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    attribute = nodes.new('ShaderNodeAttribute')
    attribute.attribute_type, attribute.attribute_name = 'INSTANCER', "ifs_color"
    shader = nodes.new('ShaderNodeBsdfPrincipled')
    output = nodes.new('ShaderNodeOutputMaterial')
    links.new(attribute.outputs["Color"], shader.inputs["Base Color"])
    links.new(attribute.outputs["Alpha"], shader.inputs["Alpha"])
    links.new(shader.outputs["BSDF"], output.inputs["Surface"])
    attribute.location, shader.location, output.location = (-300, 0), (0, 0), (300, 0)
    return mat


def prototype_collection(name, names, meshes, mat):
    """The primitives, each once, in a collection outside the scene (the node tree instances them;
    children are taken in name order, so the names start with the primitive index)."""
    collection = bpy.data.collections.get(f"{name} primitives") or bpy.data.collections.new(f"{name} primitives")
    for obj in list(collection.objects):
        mesh = obj.data
        bpy.data.objects.remove(obj)
        if mesh.users == 0:
            bpy.data.meshes.remove(mesh)
    for k, (primitive, data) in enumerate(zip(names, meshes)):
        mesh = bpy.data.meshes.new(f"{name} {primitive}")
        mesh_data.fill_mesh(mesh, data["positions"], data["triangles"], normals=data["normals"])
        mesh.materials.append(mat)
        collection.objects.link(bpy.data.objects.new(f"{k:03d} {primitive}", mesh))
    return collection


def node_tree(name, prototypes):
    """Instance on Points: primitive "ifs_primitive" of the collection, rotated so the primitive's
    x and y axes follow "ifs_axis_x" and "ifs_axis_y" (the leaf's frame), scaled by "ifs_scale"."""
    tree = bpy.data.node_groups.get(f"{name} instances")
    if tree is None:
        tree = bpy.data.node_groups.new(f"{name} instances", 'GeometryNodeTree')
        tree.inputs.new('NodeSocketGeometry', "Geometry")
        tree.outputs.new('NodeSocketGeometry', "Geometry")
    nodes, links = tree.nodes, tree.links
    nodes.clear()
    group_in, group_out = nodes.new('NodeGroupInput'), nodes.new('NodeGroupOutput')

    def attribute(attribute_name, data_type):
        node = nodes.new('GeometryNodeInputNamedAttribute')
        node.data_type = data_type
        node.inputs["Name"].default_value = attribute_name
        return next(o for o in node.outputs if o.enabled)

    collection = nodes.new('GeometryNodeCollectionInfo')
    collection.inputs["Collection"].default_value = prototypes
    collection.inputs["Separate Children"].default_value = True
    collection.inputs["Reset Children"].default_value = True
    align_x = nodes.new('FunctionNodeAlignEulerToVector')
    align_x.axis = 'X'
    align_y = nodes.new('FunctionNodeAlignEulerToVector')
    align_y.axis, align_y.pivot_axis = 'Y', 'X'
    place = nodes.new('GeometryNodeInstanceOnPoints')
    place.inputs["Pick Instance"].default_value = True
    links.new(group_in.outputs["Geometry"], place.inputs["Points"])
    links.new(collection.outputs["Geometry"], place.inputs["Instance"])
    links.new(attribute("ifs_primitive", 'INT'), place.inputs["Instance Index"])
    links.new(attribute("ifs_axis_x", 'FLOAT_VECTOR'), align_x.inputs["Vector"])
    links.new(align_x.outputs["Rotation"], align_y.inputs["Rotation"])
    links.new(attribute("ifs_axis_y", 'FLOAT_VECTOR'), align_y.inputs["Vector"])
    links.new(align_y.outputs["Rotation"], place.inputs["Rotation"])
    links.new(attribute("ifs_scale", 'FLOAT'), place.inputs["Scale"])
    links.new(place.outputs["Instances"], group_out.inputs["Geometry"])
    return tree


register_generator(InstancesGenerator())
