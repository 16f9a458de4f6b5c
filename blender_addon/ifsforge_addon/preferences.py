"""Add-on preferences (Edit > Preferences > Add-ons > ifsforge): where files of unsaved
sessions go, the resolutions new scenes start with, and how many threads the core may use."""
import bpy
from bpy.app.handlers import persistent
from bpy.props import IntProperty, StringProperty

import ifsforge

from .properties import IFSFORGE_PG_settings


def _default(name):
    """The scene setting's own default (kept in one place: properties.py)."""
    return IFSFORGE_PG_settings.__annotations__[name].keywords["default"]


def _threads_changed(self, context):
    ifsforge.set_default_threads(self.threads)


class IFSFORGE_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    cache_folder: StringProperty(
        name="Cache folder", subtype='DIR_PATH',
        description="Where files generated before the .blend is saved go (empty: the user cache). They move "
                    "beside the .blend when it is saved")
    image_size: IntProperty(name="Image size", min=16, max=16384, default=_default("image_size"),
                            description="Default pixels per side of generated images")
    volume_resolution: IntProperty(name="Volume resolution", min=8, max=2048, default=_default("volume_resolution"),
                                   description="Default voxels along the longest side")
    terrain_resolution: IntProperty(name="Terrain resolution", min=17, max=4097,
                                    default=_default("terrain_resolution"),
                                    description="Default samples along each side of a terrain")
    threads: IntProperty(name="Threads", min=0, max=1024, default=0, update=_threads_changed,
                         description="Threads the ifsforge core uses (0: all cores); results do not depend on it")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.prop(self, "cache_folder")
        layout.prop(self, "threads")
        col = layout.column(heading="New scenes")
        col.prop(self, "image_size")
        col.prop(self, "volume_resolution")
        col.prop(self, "terrain_resolution")


def get():
    """The preferences (None while the add-on is not enabled through addon_utils)."""
    addon = bpy.context.preferences.addons.get(__package__)
    return addon.preferences if addon is not None else None


DEFAULTS = ("image_size", "volume_resolution", "terrain_resolution")


@persistent
def apply_defaults(*args):
    """A new (unsaved) file's scenes start from the preferences' resolutions."""
    prefs = get()
    if prefs is None or bpy.data.filepath:
        return
    for scene in bpy.data.scenes:
        for name in DEFAULTS:
            setattr(scene.ifsforge.settings, name, getattr(prefs, name))


classes = (IFSFORGE_AP_preferences,)


def register():
    prefs = get()
    if prefs is not None:
        ifsforge.set_default_threads(prefs.threads)
    bpy.app.handlers.load_post.append(apply_defaults)


def unregister():
    bpy.app.handlers.load_post.remove(apply_defaults)
    ifsforge.set_default_threads(0)
