"""Generated files follow the .blend: files made before the first save (in this session's cache
folder) move beside it, into //<blend>_ifsforge/, on save, with relative paths; a .blend opened
where its files are missing (copied without its folder, or to another machine) regenerates them,
since every output is deterministic. Regenerate Missing does the same in one click."""
import os
import shutil
import types

import bpy
from bpy.app.handlers import persistent

from . import outputs, state
from .operators_generate import regenerate_now

_saving = []  # set while the handler saves again (its own save_post must not recurse)


def owners():
    """Every generated object and image of the file."""
    return [o for o in (*bpy.data.objects, *bpy.data.images) if state.generated(o)]


def _retarget(old, new):
    """Points every datablock (owner records, volumes, images) reading `old` at `new`."""
    for owner in owners():
        if owner.ifsforge.output and same(owner.ifsforge.output, old):
            owner.ifsforge.output = outputs.stored(new)
    for block in (*bpy.data.volumes, *bpy.data.images):
        if block.filepath and same(block.filepath, old):
            block.filepath = outputs.stored(new)


def same(stored, path):
    return os.path.abspath(bpy.path.abspath(stored)) == os.path.abspath(path)


def relocate(scene):
    """Moves the files of this session's cache folder that datablocks use into the .blend's
    folder; returns how many moved."""
    session = os.path.abspath(outputs.session_folder())
    moved = 0
    for owner in owners():
        if not owner.ifsforge.output:
            continue
        old = os.path.abspath(bpy.path.abspath(owner.ifsforge.output))
        if os.path.dirname(old) != session or not os.path.isfile(old):
            continue
        new = str(outputs.folder(scene) / os.path.basename(old))
        shutil.move(old, new)
        _retarget(old, new)
        moved += 1
    return moved


def missing():
    """Generated owners whose file is gone (baked ones play their baked files instead)."""
    return [o for o in owners() if o.ifsforge.output and not o.ifsforge.baked
            and not os.path.isfile(bpy.path.abspath(o.ifsforge.output))]


def regenerate_missing(scene):
    """Regenerates every owner whose file is missing; returns the error messages."""
    context = types.SimpleNamespace(scene=scene)
    return [error for error in (regenerate_now(context, owner) for owner in missing()) if error]


@persistent
def on_save(*args):
    if _saving or not bpy.data.filepath:
        return
    if relocate(bpy.context.scene):
        _saving.append(True)
        try:  # the file just written still names the old places
            bpy.ops.wm.save_mainfile(filepath=bpy.data.filepath)
        finally:
            _saving.clear()


@persistent
def on_load(*args):
    if not bpy.data.filepath or not missing():
        return
    for error in regenerate_missing(bpy.context.scene):
        print(f"ifsforge: {error}")


class IFSFORGE_OT_regenerate_missing(bpy.types.Operator):
    """Regenerate every ifsforge file this .blend uses that is missing (they are deterministic)"""
    bl_idname = "ifsforge.regenerate_missing"
    bl_label = "Regenerate Missing Files"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return bool(missing())

    def execute(self, context):
        count = len(missing())
        errors = regenerate_missing(context.scene)
        for error in errors:
            self.report({'ERROR'}, error)
        self.report({'INFO'}, f"regenerated {count - len(errors)} of {count} missing files")
        return {'CANCELLED'} if errors else {'FINISHED'}


classes = (IFSFORGE_OT_regenerate_missing,)


def register():
    bpy.app.handlers.save_post.append(on_save)
    bpy.app.handlers.load_post.append(on_load)


def unregister():
    bpy.app.handlers.load_post.remove(on_load)
    bpy.app.handlers.save_post.remove(on_save)
