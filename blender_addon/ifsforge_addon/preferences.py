"""Add-on preferences (Edit > Preferences > Add-ons > ifsforge): where files of unsaved
sessions go, the resolutions new scenes start with, and how many threads the core may use."""
import bpy
from bpy.props import IntProperty, StringProperty

import ifsforge


def _threads_changed(self, context):
    ifsforge.set_default_threads(self.threads)


class IFSFORGE_AP_preferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    cache_folder: StringProperty(
        name="Cache folder", subtype='DIR_PATH',
        description="Where files generated before the .blend is saved go (empty: the user cache). They move "
                    "beside the .blend when it is saved")
    image_size: IntProperty(name="Image size", min=16, max=16384, default=1024,
                            description="Default pixels per side of generated images")
    volume_resolution: IntProperty(name="Volume resolution", min=8, max=2048, default=256,
                                   description="Default voxels along the longest side")
    terrain_resolution: IntProperty(name="Terrain resolution", min=17, max=4097, default=257,
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


def apply_defaults(settings):
    """Starts a scene's settings from the preferences' resolutions."""
    prefs = get()
    if prefs is not None:
        for name in DEFAULTS:
            setattr(settings, name, getattr(prefs, name))


classes = (IFSFORGE_AP_preferences,)


def register():
    prefs = get()
    if prefs is not None:
        ifsforge.set_default_threads(prefs.threads)


def unregister():
    ifsforge.set_default_threads(0)
