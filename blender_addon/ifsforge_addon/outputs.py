"""Where generated files go: the scene's cache folder if set, else a folder next to the saved
.blend (stored as a //relative path so the project can move), else a folder of this session
in the cache folder of the add-on preferences or the user cache (so unsaved sessions never
overwrite each other's files; files.py moves them beside the .blend when it is saved)."""
import os
import re
import time
from pathlib import Path

import bpy


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
    path.mkdir(parents=True, exist_ok=True)
    return path


def file_name(stem, suffix):
    """A safe file name."""
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", stem).strip("._") or "ifsforge"
    return f"{stem}{suffix}"


def path_for(scene, stem, suffix):
    return str(folder(scene) / file_name(stem, suffix))


def remove_unused(path):
    """Deletes a file an ifsforge datablock no longer uses, unless a volume or an image still
    reads it."""
    path = os.path.abspath(path)
    users = [v.filepath for v in bpy.data.volumes] + [i.filepath for i in bpy.data.images]
    if any(os.path.abspath(bpy.path.abspath(p)) == path for p in users if p):
        return
    if os.path.isfile(path):
        os.remove(path)


def stored(path):
    """How a path is kept on a datablock: relative to the .blend when the .blend is saved."""
    if bpy.data.filepath:
        try:
            return bpy.path.relpath(path)
        except ValueError:  # another drive
            return path
    return path
