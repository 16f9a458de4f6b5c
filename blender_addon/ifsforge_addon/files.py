"""Generated files and the .blend. Every file is named by the digest of what made it
(generators.output_path), so a path always means the same contents and no file is rewritten:
each state the undo stack can return to names a file that is right for it, as long as that file
still exists. To keep it so:
- Regenerate never deletes the file it replaces (an undo step may name it);
- on save, files made before the first save (in this session's cache folder) and fractal-texture
  files are copied beside the .blend into //<blend>_ifsforge/, and the saved paths name the
  copies (relative); the originals stay for the undo steps that name them;
- on save, files of //<blend>_ifsforge/ that neither the saved state nor this session (what it
  generated, copied or loaded: an undo step may name it) uses are deleted;
- when the session ends (quit, or another file is opened: the undo steps are gone), the files
  this session made that the last saved state does not use are deleted, and the session's cache
  folder with them.
A file that is missing all the same (a .blend copied without its folder, another machine) is
made again, since every output is deterministic: on load, after undo or redo, and by
Regenerate Missing Files."""
import atexit
import os
import re
import shutil
import types
from pathlib import Path

import bpy
from bpy.app.handlers import persistent

from . import outputs, state
from .operators_generate import regenerate_now

from .outputs import CODE_KEY
DIGEST = re.compile(r"-[0-9a-f]{12}")  # what the names of generated files hold
SUFFIXES = (".vdb", ".png", ".pifs")

_saving = []  # set while the handler saves again (its own save_post must not recurse)
_saved = set()  # the files the last saved (or loaded) state uses


def owners():
    """Every generated object and image of the file."""
    return [o for o in (*bpy.data.objects, *bpy.data.images) if state.generated(o)]


class Reference:
    """One datablock's path to a file: read with get(), repointed with set()."""

    def __init__(self, block, key, attribute=True):
        self.block, self.key, self.attribute = block, key, attribute

    def get(self):
        value = getattr(self.block, self.key) if self.attribute else self.block.get(self.key, "")
        return os.path.abspath(bpy.path.abspath(value)) if isinstance(value, str) and value else ""

    def set(self, path):
        if self.attribute:
            setattr(self.block, self.key, outputs.stored(path))
        else:
            self.block[self.key] = outputs.stored(path)


def references():
    """Every path to a file that the add-on's datablocks (and what they made) hold."""
    found = [Reference(owner.ifsforge, "output") for owner in owners()]
    found += [Reference(v, "filepath") for v in bpy.data.volumes if v.filepath and not v.is_sequence]
    found += [Reference(i, "filepath") for i in bpy.data.images if i.filepath and i.source == 'FILE']
    found += [Reference(i, CODE_KEY, attribute=False) for i in bpy.data.images if CODE_KEY in i]
    return [r for r in found if r.get()]


def used():
    """The absolute paths the current state uses."""
    return {r.get() for r in references()}


def in_session_folder(path):
    """True for a file of a session's cache folder (this session's or an earlier one's)."""
    parent = Path(path).parent
    return parent.name.startswith("session-") and parent.parent == outputs.session_folder().parent


def relocate(scene):
    """Copies the files of session cache folders that datablocks use (generated objects and images,
    fractal textures and their codes) into the .blend's folder and repoints those datablocks at the
    copies; returns how many datablocks were repointed. The
    originals stay: an undo step may still name them."""
    target = outputs.folder(scene)
    repointed = 0
    for reference in references():
        old = reference.get()
        if not in_session_folder(old) or Path(old).parent == target:
            continue
        new = target / os.path.basename(old)
        if not new.is_file():
            if not os.path.isfile(old):
                continue  # gone: made again when the .blend is opened
            shutil.copyfile(old, new)
        outputs.note(new)
        reference.set(str(new))
        repointed += 1
    return repointed


def blend_folder():
    """//<blend>_ifsforge/ of the saved .blend, or None."""
    if not bpy.data.filepath:
        return None
    blend = Path(bpy.data.filepath)
    return blend.parent / f"{blend.stem}_ifsforge"


def generated_files(folder):
    """The add-on's files directly in `folder` (bake/ and anything else the user put there aside)."""
    if folder is None or not folder.is_dir():
        return []
    return [p for p in folder.iterdir()
            if p.is_file() and p.suffix in SUFFIXES and DIGEST.search(p.name)]


def clean_on_save():
    """Deletes files of the .blend's folder that nothing can name any more: neither the saved
    state nor this session (an undo step may name what it made, copied or loaded)."""
    keep = used() | outputs.handed_out()
    for path in generated_files(blend_folder()):
        if os.path.abspath(path) not in keep:
            path.unlink()


def end_session():
    """The undo steps are gone: deletes what this session made that the last saved state does not
    use, and its cache folder."""
    for path in outputs.handed_out() - _saved:
        folder = Path(path).parent
        if (in_session_folder(path) or folder.name.endswith("_ifsforge")) and os.path.isfile(path):
            os.remove(path)
    for folder in outputs.session_folders():
        shutil.rmtree(folder, ignore_errors=True)
    outputs.forget()


def missing():
    """Generated owners whose file is gone (baked ones play their baked files instead), and
    fractal textures whose decoded picture is gone."""
    gone = [o for o in owners() if o.ifsforge.output and not o.ifsforge.baked
            and not os.path.isfile(bpy.path.abspath(o.ifsforge.output))]
    return gone + [i for i in bpy.data.images if CODE_KEY in i and i.filepath
                   and not os.path.isfile(bpy.path.abspath(i.filepath))]


def regenerate_missing(scene):
    """Makes every missing file again; returns the error messages."""
    from . import fractal_texture  # (it imports panels, which import this module)
    context = types.SimpleNamespace(scene=scene)
    errors = []
    for owner in missing():
        if isinstance(owner, bpy.types.Image) and not state.generated(owner):
            errors.append(fractal_texture.decode_again(owner))
        else:
            errors.append(regenerate_now(context, owner))
    return [error for error in errors if error]


def _regenerate_missing(*args):
    if not missing():
        return
    for error in regenerate_missing(bpy.context.scene):
        print(f"ifsforge: {error}")


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
    clean_on_save()
    _saved.clear()
    _saved.update(used())


@persistent
def on_load_pre(*args):
    end_session()


@persistent
def on_load(*args):
    _saved.clear()
    _saved.update(used())
    for path in _saved:
        outputs.note(path)
    if bpy.data.filepath:
        _regenerate_missing()


@persistent
def on_undo(*args):
    """A state whose file is gone (deleted by hand, or by an older version): made again."""
    _regenerate_missing()


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

HANDLERS = (("save_post", on_save), ("load_pre", on_load_pre), ("load_post", on_load), ("undo_post", on_undo),
            ("redo_post", on_undo))


def register():
    for name, handler in HANDLERS:
        getattr(bpy.app.handlers, name).append(handler)
    atexit.register(end_session)


def unregister():
    atexit.unregister(end_session)
    for name, handler in reversed(HANDLERS):
        getattr(bpy.app.handlers, name).remove(handler)
