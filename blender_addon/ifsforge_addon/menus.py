"""Blender's own places for the add-on: Add (Shift+A) > IFS, File > Import > "IFS system" and
File > Export > "POV-Ray scene", the operator presets shipped for the samples (copied where
Blender's preset menus look, beside the user's own), and the glTF importer's numpy fix."""
import shutil
from pathlib import Path

import bpy
import numpy

from . import generators

# (generator kind, menu text, icon) in the order of the Add menu.
ADD_ENTRIES = (('VOLUME', "Volume", 'VOLUME_DATA'), ('INSTANCES', "Instances", 'MOD_PARTICLE_INSTANCE'),
               ('TERRAIN', "Terrain", 'RNDCURVE'), ('MESH', "Iso-surface", 'MESH_DATA'),
               ('IMAGE', "Image", 'IMAGE_DATA'))
SHIPPED_PRESETS = Path(__file__).resolve().parent / "operator_presets"


class IFSFORGE_MT_add(bpy.types.Menu):
    """Objects generated from the edited iterated function system, at the 3D cursor"""
    bl_idname = "IFSFORGE_MT_add"
    bl_label = "IFS"

    def draw(self, context):
        layout = self.layout
        layout.operator_context = 'INVOKE_REGION_WIN'  # the background job with progress and Esc
        for kind, text, icon in ADD_ENTRIES:
            if generators.registered(kind):
                op = layout.operator(f"ifsforge.generate_{kind.lower()}", text=text, icon=icon)
                if kind == 'IMAGE':
                    op.in_viewport = True


def draw_add(self, context):
    self.layout.menu(IFSFORGE_MT_add.bl_idname, icon='OUTLINER_OB_POINTCLOUD')


def draw_import(self, context):
    self.layout.operator("ifsforge.import_system", text="IFS system (.json, .ifs)")


def draw_export(self, context):
    self.layout.operator("ifsforge.export_povray_scene", text="POV-Ray scene (.pov)")


def install_presets():
    """Copies the shipped operator presets into the user's preset folders (never over a file of
    the same name: the user may have changed it), where the F9 panel's preset menu lists them."""
    for folder in sorted(p for p in SHIPPED_PRESETS.iterdir() if p.is_dir()):
        target = Path(bpy.utils.user_resource('SCRIPTS', path=f"presets/operator/{folder.name}", create=True))
        for preset in folder.glob("*.py"):
            if not (target / preset.name).exists():
                shutil.copyfile(preset, target / preset.name)


def patch_numpy():
    """Blender 3.4's glTF importer uses numpy.bool, which numpy 1.24 removed: give it back (the
    builtin it was an alias of) so File > Import > glTF reads the .glb files ifsforge writes."""
    if "bool" not in numpy.__dict__:
        numpy.bool = bool


classes = (IFSFORGE_MT_add,)


def register():
    patch_numpy()
    install_presets()
    bpy.types.VIEW3D_MT_add.append(draw_add)
    bpy.types.TOPBAR_MT_file_import.append(draw_import)
    bpy.types.TOPBAR_MT_file_export.append(draw_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(draw_export)
    bpy.types.TOPBAR_MT_file_import.remove(draw_import)
    bpy.types.VIEW3D_MT_add.remove(draw_add)
