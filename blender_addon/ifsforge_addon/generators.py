"""Generators: each turns a system and its settings into a file with the ifsforge module (on
a worker thread, no bpy) and then into a datablock (on the main thread). One module per
kind; this one holds what they share and the registry."""
import hashlib
import json

import bpy
from mathutils import Matrix, Vector

import ifsforge

from . import outputs
from .properties import restore

_registry = {}


class Generator:
    kind = 'NONE'
    label = ""
    suffix = ""
    datablock = "object"  # or "image": where the parameters are stored
    needs = ()  # the ifsforge functions work() calls
    feature = ""  # what the user misses without them, e.g. "volumes"
    default_sample = "barnsley_fern.json"  # what an empty design (a fresh scene) generates from

    def uses_system(self, settings):
        """False when the output does not depend on the system (`settings`: plain values)."""
        return True

    def missing(self):
        """'' when the ifsforge module provides what this generator needs, else why not."""
        absent = [name for name in self.needs if not hasattr(ifsforge, name)]
        return f"this ifsforge build has no {self.feature} ({', '.join(absent)})" if absent else ""

    def draw(self, layout, settings, system):
        """The generator's settings in its panel (`system`: the edited ifsforge.Ifs or None)."""

    def resolve(self, settings):
        """Runs on the main thread before work(): settings that need bpy (paths relative to
        the .blend) made plain. Returns the settings to hand to work()."""
        return settings

    def work(self, system, settings, path, progress):
        """Runs on a worker thread: writes `path`, returns a dict for apply()."""
        raise NotImplementedError

    def apply(self, context, owner, result, name):
        """Runs on the main thread: creates (owner None) or updates the datablock."""
        raise NotImplementedError


def node_material(name):
    """The material `name` (made if new) with an empty node tree: (material, nodes, links)."""
    mat = bpy.data.materials.get(name) or bpy.data.materials.new(name)
    mat.use_nodes = True
    mat.node_tree.nodes.clear()
    return mat, mat.node_tree.nodes, mat.node_tree.links


def register_generator(generator):
    _registry[generator.kind] = generator
    return generator


def get(kind):
    return _registry[kind]


def registered(kind):
    return kind in _registry


def unique_name(generator, base):
    """`base`, or `base.001`, ... : a name no datablock of the generator's type has yet, so
    that a new datablock's file never overwrites another's."""
    taken = bpy.data.images if generator.datablock == "image" else bpy.data.objects
    name, k = base, 0
    while name in taken:
        k += 1
        name = f"{base}.{k:03d}"
    return name


def animated(owner):
    """True when an F-curve of the owner's action, of one of its NLA strips' actions, or a driver
    writes one of its stored values."""
    data = getattr(owner, "animation_data", None)
    if not data:
        return False
    actions = [data.action] + [strip.action for track in data.nla_tracks for strip in track.strips]
    curves = [fc for action in actions if action for fc in action.fcurves] + list(data.drivers)
    return any(fc.data_path.startswith("ifsforge.") for fc in curves)


def digest(values):
    """A digest of a properties.snapshot() minus what does not shape the output (the active
    map of the list): equal digests, equal outputs."""
    text = json.dumps({k: v for k, v in values.items() if k != "active_map"}, sort_keys=True, default=list)
    return hashlib.sha1(text.encode()).hexdigest()


def without_system(values):
    """A snapshot whose system is left out: what names the file of an output made without one."""
    return {key: value for key, value in values.items() if key not in ("record", "morph", "active_map")}


def output_path(context, generator, name, values):
    """Where the generator writes (None for generators that write nothing): the datablock's
    name and a digest of everything the output depends on. Outputs are deterministic, so equal
    names mean equal contents, and a changed parameter (a new frame of an animation, an edit)
    means a new file: Blender keeps the grids of a .vdb it has read by path, so rewriting a file
    under its old name would not show."""
    if not generator.suffix:
        return None
    shaping = {k: v for k, v in values.items() if k != "active_map"}
    text = json.dumps([generator.kind, ifsforge.__version__, shaping], sort_keys=True, default=list)
    digest = hashlib.sha1(text.encode()).hexdigest()[:12]
    return outputs.path_for(context.scene, f"{name}-{digest}", generator.suffix)


def store(owner, generator, source, result):
    """Records on the datablock what came out, and what it was made from when `source` (a
    properties.snapshot) is given: a new datablock keeps the design it was generated from."""
    data = owner.ifsforge
    if source is not None:
        restore(source, data.system, data.settings)
    data.kind = generator.kind
    # The previous file stays: an undo step may name it (files.py deletes what nothing can name).
    data.output = outputs.stored(result["path"]) if result.get("path") else ""
    data.summary = result.get("summary", "")


def image_empty(context, image):
    """An image empty showing `image` at the 3D cursor (as Add > Image > Reference makes), active
    and selected: what Add > IFS > Image puts in the viewport."""
    obj = bpy.data.objects.new(image.name, None)
    obj.empty_display_type = 'IMAGE'
    obj.empty_display_size = 2.0
    obj.data = image
    obj.location = context.scene.cursor.location
    link_object(context, obj)
    return obj


def system_matrix(obj):
    """The 4x4 matrix taking the system's coordinates to the world's for a generated object,
    whose data sits around its origin (the system's point obj.ifsforge.origin)."""
    return obj.matrix_world @ Matrix.Translation(-Vector(obj.ifsforge.origin))


def link_object(context, obj):
    """Puts a new object in the active collection and makes it the active, selected one."""
    context.collection.objects.link(obj)
    for other in context.view_layer.objects.selected:
        other.select_set(False)
    obj.select_set(True)
    context.view_layer.objects.active = obj


def owner_by_name(generator, name):
    """The datablock a generator stores its parameters on, by name (None when gone)."""
    collection = bpy.data.images if generator.datablock == "image" else bpy.data.objects
    return collection.get(name)
