"""File > Export > POV-Ray scene: every ifsforge object of the scene (pov_scene) through the
active camera, optionally rendered by the real POV-Ray (ifsforge.render_povray) into a PNG beside
the scene, loaded as an image."""
import os

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

import ifsforge

from . import pov_scene
from .operators_generate import report_error


class IFSFORGE_OT_export_povray_scene(bpy.types.Operator, ExportHelper):
    """Write the scene's terrains, iso-surfaces, instances and volumes, with their colours, as a POV-Ray
    3.7 scene seen through the active camera, lit by its sun and point lights and the world colour
    (size: the scene's render resolution)"""
    bl_idname = "ifsforge.export_povray_scene"
    bl_label = "Export POV-Ray Scene"
    filename_ext = ".pov"
    filter_glob: StringProperty(default="*.pov", options={'HIDDEN'})
    render: BoolProperty(name="Render with POV-Ray", description="Also render the scene to a PNG beside it "
                         "and load it as an image")

    def execute(self, context):
        r = context.scene.render
        width, height = int(r.resolution_x * r.resolution_percentage / 100), \
            int(r.resolution_y * r.resolution_percentage / 100)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        try:
            counts = pov_scene.write_scene(self.filepath, context, width, height)
            wm.progress_update(40)
            if self.render:
                png = os.path.splitext(self.filepath)[0] + ".png"
                ifsforge.render_povray(self.filepath, png, width, height,
                                       progress=lambda f: wm.progress_update(40 + int(60 * f)) or True)
                image = bpy.data.images.load(png, check_existing=True)
                image.reload()
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        finally:
            wm.progress_end()
        written = ", ".join(f"{n} {kind.lower()}" for kind, n in sorted(counts.items()))
        self.report({'INFO'}, f"wrote {self.filepath}: {written}")
        return {'FINISHED'}


classes = (IFSFORGE_OT_export_povray_scene,)
