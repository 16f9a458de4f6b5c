"""Animation: keyframed system values (or a morph factor) regenerate the datablocks made from
them on every frame, renders included. The continuity theorem (seed chapter 4) is what makes
the frames change smoothly: the attractor moves continuously with the coefficients.

The work happens in frame_change_pre, before the frame is evaluated, so that the render of a
frame sees the datablock made for it; the keyframed values of the new frame are therefore
evaluated here (the animation system writes the same values again right after)."""
import types

import bpy
from bpy.app.handlers import persistent

from . import generators, preview, state
from .operators_generate import regenerate_now


def animated_owners(scene):
    """Generated objects of the scene whose stored values are keyframed and set to follow."""
    return [obj for obj in scene.objects
            if state.generated(obj) and obj.ifsforge.regenerate_on_frame and generators.animated(obj)]


def apply_keyframes(owner, frame):
    """Writes the value of every "ifsforge." F-curve of the owner's action at `frame`."""
    for fcurve in owner.animation_data.action.fcurves:
        if not fcurve.data_path.startswith("ifsforge."):
            continue
        parent_path, _, name = fcurve.data_path.rpartition(".")
        parent = owner.path_resolve(parent_path)
        value = fcurve.evaluate(frame)
        current = getattr(parent, name)
        if hasattr(current, "__len__") and not isinstance(current, str):
            current[fcurve.array_index] = type(current[fcurve.array_index])(value)
        else:
            setattr(parent, name, type(current)(value))


@persistent
def on_frame_change(scene, depsgraph=None):
    context = types.SimpleNamespace(scene=scene)
    for owner in animated_owners(scene):
        apply_keyframes(owner, scene.frame_current)
        error = regenerate_now(context, owner)
        if error:
            print(f"ifsforge: frame {scene.frame_current}: {error}")


@persistent
def on_load(*args):
    state.clear()
    preview.current.__init__()


def register():
    bpy.app.handlers.frame_change_pre.append(on_frame_change)
    bpy.app.handlers.load_post.append(on_load)


def unregister():
    bpy.app.handlers.load_post.remove(on_load)
    bpy.app.handlers.frame_change_pre.remove(on_frame_change)
