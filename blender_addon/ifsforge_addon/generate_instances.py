"""CSG instances (vector recursive rendering, seed 5.8.2): ifsforge.instances places one
primitive per leaf; Blender shows them as instances of the primitive meshes on the points of
one object, driven by a geometry-node tree that reads each point's frame, scale, primitive
and colour. Materials read the colour with an Attribute node (type Instancer, "ifs_color")."""
import bpy
import numpy as np

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
    default_sample = "vector_csg_pyramid.json"

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
        reach = np.asarray(instances.scales, np.float64)[:, None]  # a primitive fills about its scale
        positions = np.asarray(instances.positions, np.float64)
        origin = mesh_data.center((positions - reach).min(axis=0), (positions + reach).max(axis=0)) \
            if len(positions) else (0.0,) * 3
        return {"path": None, "instances": instances, "origin": origin, "meshes": [p.mesh(SEGMENTS) for p in instances.primitives],
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
        mesh_data.points_mesh(mesh, np.asarray(instances.positions, np.float64) - result["origin"])
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
    """Principled BSDF whose color and alpha are each instance's "ifs_color"."""
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
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
    children are taken in name order, so the names start with the primitive index). Objects whose
    mesh the add-on made (tagged "ifsforge_primitive") are rebuilt; any other one is the user's
    replacement for the primitive of its index (Suzanne for the sphere) and is kept."""
    collection = bpy.data.collections.get(f"{name} primitives") or bpy.data.collections.new(f"{name} primitives")
    replaced = set()
    for obj in list(collection.objects):
        if obj.type == 'MESH' and "ifsforge_primitive" in obj.data:
            mesh = obj.data
            bpy.data.objects.remove(obj)
            if mesh.users == 0:
                bpy.data.meshes.remove(mesh)
        else:
            replaced.add(obj.name[:3])
    for k, (primitive, data) in enumerate(zip(names, meshes)):
        if f"{k:03d}" in replaced:
            continue
        mesh = bpy.data.meshes.new(f"{name} {primitive}")
        mesh["ifsforge_primitive"] = primitive
        mesh_data.fill_mesh(mesh, data["positions"], data["triangles"], normals=data["normals"],
                            custom_normals=True)  # a few hundred vertices: the exact normals are free
        mesh.materials.append(mat)
        collection.objects.link(bpy.data.objects.new(f"{k:03d} {primitive}", mesh))
    return collection


# The node group's inputs beyond the geometry, shown on the modifier: (socket type, name, default).
INPUTS = (('NodeSocketFloat', "Scale", 1.0), ('NodeSocketObject', "Object", None),
          ('NodeSocketCollection', "Collection", None))


def enabled(sockets):
    """The sockets a node shows for its current type (the others are hidden alternatives)."""
    return [socket for socket in sockets if socket.enabled]


def node_tree(name, prototypes):
    """Instance on Points: primitive "ifs_primitive" of the collection, rotated so the primitive's
    x and y axes follow "ifs_axis_x" and "ifs_axis_y" (the leaf's frame), scaled by "ifs_scale"
    times the input Scale. The inputs Object or Collection, when set, are instanced instead of
    the prototypes (the Object on every point; the Collection's children picked by primitive)."""
    tree = bpy.data.node_groups.get(name)
    if tree is None:
        tree = bpy.data.node_groups.new(name, 'GeometryNodeTree')
        tree.inputs.new('NodeSocketGeometry', "Geometry")
        tree.outputs.new('NodeSocketGeometry', "Geometry")
    for kind, label, default in INPUTS:
        if label not in tree.inputs:
            socket = tree.inputs.new(kind, label)
            if default is not None:
                socket.default_value = default
    nodes, links = tree.nodes, tree.links
    nodes.clear()
    group_in, group_out = nodes.new('NodeGroupInput'), nodes.new('NodeGroupOutput')

    def attribute(attribute_name, data_type):
        node = nodes.new('GeometryNodeInputNamedAttribute')
        node.data_type = data_type
        node.inputs["Name"].default_value = attribute_name
        return next(o for o in node.outputs if o.enabled)

    def instances_of(collection_socket=None, collection=None):
        node = nodes.new('GeometryNodeCollectionInfo')
        if collection_socket is not None:
            links.new(collection_socket, node.inputs["Collection"])
        else:
            node.inputs["Collection"].default_value = collection
        node.inputs["Separate Children"].default_value = True
        node.inputs["Reset Children"].default_value = True
        return node.outputs["Geometry"]

    def unless_empty(preferred, fallback):
        """`preferred` when it holds any instance, else `fallback`."""
        size = nodes.new('GeometryNodeAttributeDomainSize')
        size.component = 'INSTANCES'
        links.new(preferred, size.inputs["Geometry"])
        some = nodes.new('FunctionNodeCompare')
        some.data_type, some.operation = 'INT', 'GREATER_THAN'
        links.new(size.outputs["Instance Count"], enabled(some.inputs)[0])  # > B = 0
        switch = nodes.new('GeometryNodeSwitch')
        switch.input_type = 'GEOMETRY'
        condition, when_false, when_true = enabled(switch.inputs)
        links.new(some.outputs["Result"], condition)
        links.new(fallback, when_false)
        links.new(preferred, when_true)
        return enabled(switch.outputs)[0]

    user_object = nodes.new('GeometryNodeObjectInfo')
    user_object.inputs["As Instance"].default_value = True
    user_object.transform_space = 'ORIGINAL'
    links.new(group_in.outputs["Object"], user_object.inputs["Object"])
    chosen = unless_empty(instances_of(group_in.outputs["Collection"]), instances_of(collection=prototypes))
    chosen = unless_empty(user_object.outputs["Geometry"], chosen)
    align_x = nodes.new('FunctionNodeAlignEulerToVector')
    align_x.axis = 'X'
    align_y = nodes.new('FunctionNodeAlignEulerToVector')
    align_y.axis, align_y.pivot_axis = 'Y', 'X'
    scale = nodes.new('ShaderNodeMath')
    scale.operation = 'MULTIPLY'
    place = nodes.new('GeometryNodeInstanceOnPoints')
    place.inputs["Pick Instance"].default_value = True
    links.new(group_in.outputs["Geometry"], place.inputs["Points"])
    links.new(chosen, place.inputs["Instance"])
    links.new(attribute("ifs_primitive", 'INT'), place.inputs["Instance Index"])
    links.new(attribute("ifs_axis_x", 'FLOAT_VECTOR'), align_x.inputs["Vector"])
    links.new(align_x.outputs["Rotation"], align_y.inputs["Rotation"])
    links.new(attribute("ifs_axis_y", 'FLOAT_VECTOR'), align_y.inputs["Vector"])
    links.new(align_y.outputs["Rotation"], place.inputs["Rotation"])
    links.new(attribute("ifs_scale", 'FLOAT'), scale.inputs[0])
    links.new(group_in.outputs["Scale"], scale.inputs[1])
    links.new(scale.outputs[0], place.inputs["Scale"])
    links.new(place.outputs["Instances"], group_out.inputs["Geometry"])
    return tree


register_generator(InstancesGenerator())
