"""Where generated files go: the scene's cache folder if set, else a folder next to the saved
.blend (stored as a //relative path so the project can move), else a folder of this session
in the cache folder of the add-on preferences or the user cache (so unsaved sessions never
overwrite each other's files; files.py moves them beside the .blend when it is saved)."""
import os
import re
import time
from pathlib import Path

import bpy


CODE_KEY = "ifsforge_pifs"  # a fractal texture's custom property: the path of its .pifs code
SIZE_KEY = "ifsforge_pifs_size"  # and the size it was decoded at

SESSION = time.strftime("session-%Y%m%d-%H%M%S-") + str(os.getpid())


def session_folder():
    """Where files go before the .blend is saved: the add-on preferences' cache folder, else
    the user cache; one folder per session so unsaved sessions never share files."""
    addon = bpy.context.preferences.addons.get(__package__)
    base = addon.preferences.cache_folder if addon is not None else ""
    if not base:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "ifsforge" / "blender"
    return Path(bpy.path.abspath(str(base))) / SESSION


def folder(scene):
    if scene.ifsforge.cache_folder:
        path = Path(bpy.path.abspath(scene.ifsforge.cache_folder))
    elif bpy.data.filepath:
        blend = Path(bpy.data.filepath)
        path = blend.parent / f"{blend.stem}_ifsforge"
    else:
        path = session_folder()
        _session_folders.add(str(path))
    path.mkdir(parents=True, exist_ok=True)
    return path


def file_name(stem, suffix):
    """A safe file name."""
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", stem).strip("._") or "ifsforge"
    return f"{stem}{suffix}"


def path_for(scene, stem, suffix):
    """Where a generated file goes (recorded as handed out)."""
    return note(folder(scene) / file_name(stem, suffix))


# What this session handed out: every file it made or copied, and those the file it opened uses
# (an undo step may name any of them: files.py deletes none of them before the session ends).
_handed_out = set()
_session_folders = set()


def note(path):
    """Records a file this session made (or copied, or found in the file it opened)."""
    _handed_out.add(os.path.abspath(str(path)))
    return str(path)


def handed_out():
    return set(_handed_out)


def session_folders():
    return set(_session_folders)


def forget():
    """A new session: its undo steps name none of the earlier files."""
    _handed_out.clear()
    _session_folders.clear()


def stored(path):
    """How a path is kept on a datablock: relative to the .blend when the .blend is saved."""
    if bpy.data.filepath:
        try:
            return bpy.path.relpath(path)
        except ValueError:  # another drive
            return path
    return path
