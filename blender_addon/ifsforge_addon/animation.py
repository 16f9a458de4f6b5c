"""Animation: a generated object follows its stored values frame by frame, whatever changes them
(keyframes, drivers, NLA strips, scripts). After each frame's evaluation the values of the
evaluated object (animation applied) are compared by digest with those it was built from, and
it is rebuilt when they differ. The rebuild happens in frame_change_post: Blender evaluates the
depsgraph again when a post handler changed data, so renders see the rebuilt frame. The
continuity theorem (seed chapter 4) is what makes the frames change smoothly: the attractor
moves continuously with the coefficients. Baked objects (bake.py) play their files instead."""
import types

import bpy
from bpy.app.handlers import persistent

from . import generators, preview, state
from .operators_generate import regenerate_now
from .properties import snapshot


def following(scene):
    """Generated objects of the scene that rebuild on frame changes."""
    return [obj for obj in scene.objects
            if state.generated(obj) and obj.ifsforge.regenerate_on_frame and not obj.ifsforge.baked]


def stale(owner, depsgraph):
    """The ifsforge group `owner` is to be built from when its values differ from those it was
    built from, else None: the evaluated copy's when animation (keyframes, NLA, drivers) writes
    them, else the object's own (a script's change reaches the evaluated copy only later)."""
    animated = depsgraph is not None and generators.animated(owner)
    source = (owner.evaluated_get(depsgraph) if animated else owner).ifsforge
    if generators.digest(snapshot(source.system, source.settings)) == owner.ifsforge.built_from:
        return None
    return source


@persistent
def on_frame_change(scene, depsgraph=None):
    context = types.SimpleNamespace(scene=scene)
    for owner in following(scene):
        source = stale(owner, depsgraph)
        if source is None:
            continue
        error = regenerate_now(context, owner, source)
        if error:
            print(f"ifsforge: frame {scene.frame_current}: {error}")


@persistent
def on_load(*args):
    state.clear()
    preview.current.__init__()


def register():
    bpy.app.handlers.frame_change_post.append(on_frame_change)
    bpy.app.handlers.load_post.append(on_load)


def unregister():
    bpy.app.handlers.load_post.remove(on_load)
    bpy.app.handlers.frame_change_post.remove(on_frame_change)
