"""Bake Animation: the frames of animated generated objects become data Blender plays by itself,
so a render node without ifsforge renders them. Volumes: a frame-numbered .vdb sequence (the
Volume datablock in sequence mode). Terrains and iso-surfaces: one mesh per frame in the .blend
and a geometry-node modifier picking the current frame's (built-in nodes only). Instances: the
same for their point cloud (positions and per-instance attributes), picked before the instancing
node group, which places the prototypes as it does live. Baked objects
stop rebuilding on frame changes (Free Bake turns them back)."""
import os
import shutil
from pathlib import Path

import bpy
from bpy.props import IntProperty

from . import outputs, state
from .operators_generate import report_error

BAKEABLE = {'VOLUME', 'TERRAIN', 'MESH', 'INSTANCES'}
BAKE_MODIFIER = "ifsforge bake"


def bake_folder(scene, owner):
    folder = outputs.folder(scene) / "bake" / outputs.file_name(owner.name, "")
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def bake_volumes(scene, owners, frames):
    """Every frame's .vdb copied to <name>_<frame>.vdb; the datablock reads them as a sequence."""
    sequences = {owner.name: [] for owner in owners}
    for frame in frames:
        scene.frame_set(frame)  # the frame handler rebuilds each owner whose values changed
        for owner in owners:
            source = bpy.path.abspath(owner.data.filepath)
            target = bake_folder(scene, owner) / f"{outputs.file_name(owner.name, '')}_{frame:04d}.vdb"
            shutil.copyfile(source, target)
            sequences[owner.name].append(str(target))
    for owner in owners:
        volume = owner.data
        volume.filepath = outputs.stored(sequences[owner.name][0])
        volume.is_sequence = True
        # Blender reads file number (scene frame - frame_start + 1) + frame_offset: the frame itself.
        volume.frame_start, volume.frame_duration = frames[0], len(frames)
        volume.frame_offset = frames[0] - 1
        volume.sequence_mode = 'CLIP'
        owner.ifsforge.baked = True


def bake_meshes(scene, owners, frames):
    """Every frame's mesh kept as a copy (an object per frame in a collection outside the scene),
    and a geometry-node modifier showing the one of the current frame (Blender 3.4 as Debian
    builds it has neither Alembic nor USD: its Mesh Sequence Cache cannot read anything)."""
    collections = {}
    for owner in owners:
        name = f"{owner.name} baked"
        old = bpy.data.collections.get(name)
        if old is not None:
            for obj in list(old.objects):
                bpy.data.objects.remove(obj)
            bpy.data.collections.remove(old)
        collections[owner.name] = bpy.data.collections.new(name)
    for frame in frames:
        scene.frame_set(frame)  # the frame handler rebuilds each owner whose values changed
        for owner in owners:
            mesh = owner.data.copy()
            mesh.name = f"{owner.name} {frame:04d}"
            collections[owner.name].objects.link(bpy.data.objects.new(f"{frame:08d}", mesh))
    for owner in owners:
        modifier = owner.modifiers.get(BAKE_MODIFIER) or owner.modifiers.new(BAKE_MODIFIER, 'NODES')
        modifier.node_group = frame_switch(f"{owner.name} baked", collections[owner.name], frames[0], len(frames))
        if owner.modifiers[0] != modifier:  # instances: the frame's points first, then the instancing
            with bpy.context.temp_override(object=owner):
                bpy.ops.object.modifier_move_to_index(modifier=modifier.name, index=0)
        owner.ifsforge.baked = True


def frame_switch(name, collection, start, count):
    """Geometry nodes: the child of `collection` number clamp(frame - start, 0, count - 1)
    (children in name order), realized."""
    tree = bpy.data.node_groups.get(name) or bpy.data.node_groups.new(name, 'GeometryNodeTree')
    tree.nodes.clear()
    if not tree.outputs:
        tree.inputs.new('NodeSocketGeometry', "Geometry")
        tree.outputs.new('NodeSocketGeometry', "Geometry")
    nodes, links = tree.nodes, tree.links
    output = nodes.new('NodeGroupOutput')
    info = nodes.new('GeometryNodeCollectionInfo')
    info.inputs["Collection"].default_value = collection
    info.inputs["Separate Children"].default_value = True
    info.inputs["Reset Children"].default_value = True
    time = nodes.new('GeometryNodeInputSceneTime')
    clamp = nodes.new('ShaderNodeClamp')
    offset = nodes.new('ShaderNodeMath')
    offset.operation = 'SUBTRACT'
    offset.inputs[1].default_value = start
    clamp.inputs["Min"].default_value, clamp.inputs["Max"].default_value = 0.0, count - 1
    index = nodes.new('GeometryNodeInputIndex')
    other = nodes.new('FunctionNodeCompare')
    other.data_type, other.operation = 'FLOAT', 'NOT_EQUAL'
    other.inputs["Epsilon"].default_value = 0.5
    delete = nodes.new('GeometryNodeDeleteGeometry')
    delete.domain = 'INSTANCE'
    realize = nodes.new('GeometryNodeRealizeInstances')
    links.new(time.outputs["Frame"], offset.inputs[0])
    links.new(offset.outputs[0], clamp.inputs["Value"])
    links.new(index.outputs["Index"], other.inputs["A"])
    links.new(clamp.outputs["Result"], other.inputs["B"])
    links.new(info.outputs["Geometry"], delete.inputs["Geometry"])
    links.new(other.outputs["Result"], delete.inputs["Selection"])
    links.new(delete.outputs["Geometry"], realize.inputs["Geometry"])
    links.new(realize.outputs["Geometry"], output.inputs["Geometry"])
    return tree


class IFSFORGE_OT_bake_animation(bpy.types.Operator):
    """Write the frames of the scene's animated ifsforge objects as data Blender plays by itself (.vdb
    sequences for volumes, one mesh per frame in the .blend for the others), so the scene renders
    without the add-on"""
    bl_idname = "ifsforge.bake_animation"
    bl_label = "Bake Animation"
    bl_options = {'REGISTER', 'UNDO'}
    frame_start: IntProperty(name="Start", default=1, min=0)
    frame_end: IntProperty(name="End", default=250, min=0)

    def invoke(self, context, event):
        self.frame_start, self.frame_end = context.scene.frame_start, context.scene.frame_end
        return context.window_manager.invoke_props_dialog(self)

    def execute(self, context):
        scene = context.scene
        if self.frame_end < self.frame_start:
            self.report({'ERROR'}, f"frame_end {self.frame_end} is before frame_start {self.frame_start}")
            return {'CANCELLED'}
        if not bpy.data.filepath and not scene.ifsforge.cache_folder:
            self.report({'ERROR'}, "save the .blend first: the baked files go beside it")
            return {'CANCELLED'}
        owners = [o for o in scene.objects if state.generated(o) and o.ifsforge.kind in BAKEABLE
                  and o.ifsforge.regenerate_on_frame and not o.ifsforge.baked]
        if not owners:
            self.report({'WARNING'},
                        "no unbaked ifsforge volume, terrain, iso-surface or instances object in the scene")
            return {'CANCELLED'}
        frames = list(range(self.frame_start, self.frame_end + 1))
        current = scene.frame_current
        try:
            bake_volumes(scene, [o for o in owners if o.ifsforge.kind == 'VOLUME'], frames)
            bake_meshes(scene, [o for o in owners if o.ifsforge.kind != 'VOLUME'], frames)
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        finally:
            scene.frame_set(current)
        self.report({'INFO'}, f"baked {len(owners)} objects, frames {frames[0]}-{frames[-1]}")
        return {'FINISHED'}


class IFSFORGE_OT_free_bake(bpy.types.Operator):
    """Forget the active object's baked frames: it rebuilds on frame changes again"""
    bl_idname = "ifsforge.free_bake"
    bl_label = "Free Bake"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return state.generated(obj) and obj.ifsforge.baked

    def execute(self, context):
        obj = context.active_object
        if obj.type == 'VOLUME':
            obj.data.is_sequence = False
        elif BAKE_MODIFIER in obj.modifiers:
            obj.modifiers.remove(obj.modifiers[BAKE_MODIFIER])
            frames = bpy.data.collections.get(f"{obj.name} baked")
            if frames is not None:
                for child in list(frames.objects):
                    mesh = child.data
                    bpy.data.objects.remove(child)
                    bpy.data.meshes.remove(mesh)
                bpy.data.collections.remove(frames)
        obj.ifsforge.baked = False
        obj.ifsforge.built_from = ""  # rebuild on the next frame
        folder = Path(outputs.folder(context.scene)) / "bake" / outputs.file_name(obj.name, "")
        if folder.is_dir() and os.path.commonpath([folder, outputs.folder(context.scene)]):
            shutil.rmtree(folder)
        return {'FINISHED'}


classes = (IFSFORGE_OT_bake_animation, IFSFORGE_OT_free_bake)
