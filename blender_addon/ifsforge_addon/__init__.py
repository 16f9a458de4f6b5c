"""ifsforge for Blender: design iterated function systems with a live preview and generate
volumes, CSG instances, terrains, palettes, iso-surfaces and images from them. Every number
comes from the `ifsforge` module (the same one the CLI and Python use); this package only
holds Blender's side: properties, operators, panels and the viewport preview."""

bl_info = {
    "name": "ifsforge",
    "author": "ifsforge",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "3D Viewport > Sidebar > IFS",
    "description": "Iterated function systems: interactive design, volumes, instances, terrains, palettes",
    "category": "Add Mesh",
}

import sys  # noqa: E402
from pathlib import Path  # noqa: E402

# install.sh BUILD_DIR bundles that build's module here; it then comes before any other.
_VENDOR = Path(__file__).resolve().parent / "vendor"
if (_VENDOR / "ifsforge").is_dir() and str(_VENDOR) not in sys.path:
    sys.path.insert(0, str(_VENDOR))

try:
    import ifsforge  # noqa: F401
except ImportError as error:  # nothing works without it: say how to get it
    raise ImportError("ifsforge add-on: the 'ifsforge' Python module is not importable in Blender "
                      f"({error}); run blender_addon/install.sh BUILD_DIR") from error
if not hasattr(ifsforge, "RenderOptions"):
    raise ImportError(f"ifsforge add-on: the ifsforge module Blender imports ({ifsforge.__file__}) is older than "
                      "the add-on; reinstall it, or run blender_addon/install.sh BUILD_DIR")

import bpy  # noqa: E402

from . import (animation, bake, files, fractal_texture, menus, operators_design, operators_export,  # noqa: E402
               operators_export_scene, operators_generate, panels, preferences, preview, properties)

# Every class the add-on registers, in order (a new module adds its `classes` here).
classes = (*preferences.classes, *properties.classes, *operators_generate.classes, *operators_design.classes,
           *operators_export.classes, *operators_export_scene.classes, *bake.classes, *files.classes, *menus.classes,
           *panels.classes, *fractal_texture.classes)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    properties.register_pointers()
    preferences.register()
    fractal_texture.register_pointers()
    preview.register()
    animation.register()
    files.register()
    menus.register()


def unregister():
    menus.unregister()
    files.unregister()
    animation.unregister()
    preview.unregister()
    fractal_texture.unregister_pointers()
    preferences.unregister()
    properties.unregister_pointers()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
