"""Export the edited system as a POV-Ray 3.7 scene: its vector IFS instance list (5.8.2) through
the vector area's exporter (ifsforge.write_pov_scene, with ifsforge.inc beside it), optionally
rendered by POV-Ray into a PNG that is loaded as an image. The JSON export is in
operators_design."""
import os

import bpy
from bpy.props import BoolProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

import ifsforge

from . import state
from .operators_generate import report_error

SCENE = ifsforge.PovSceneOptions()  # the defaults, written once in C++


class IFSFORGE_OT_export_povray(bpy.types.Operator, ExportHelper):
    """Write the system's instance list as a POV-Ray 3.7 scene (the Instances settings choose depth,
    primitives and colours)"""
    bl_idname = "ifsforge.export_povray"
    bl_label = "Export System Instances (POV-Ray)"
    filename_ext = ".pov"
    filter_glob: StringProperty(default="*.pov", options={'HIDDEN'})
    width: IntProperty(name="Width", min=16, max=16384, default=SCENE.width)
    height: IntProperty(name="Height", min=16, max=16384, default=SCENE.height)
    render: BoolProperty(name="Render with POV-Ray", description="Also render the scene to a PNG beside it "
                         "and load it as an image")

    @classmethod
    def poll(cls, context):
        if not hasattr(ifsforge, "write_pov_scene"):
            cls.poll_message_set("this ifsforge build has no POV-Ray exporter")
            return False
        return True

    def invoke(self, context, event):
        self.filepath = (state.target(context)[1].name or "system") + ".pov"
        return ExportHelper.invoke(self, context, event)

    def execute(self, context):
        _, pg, settings = state.target(context)
        wm = context.window_manager
        wm.progress_begin(0, 100)
        try:
            system = state.system_of(pg)
            instances = ifsforge.instances(system, depth=settings.instance_depth,
                                           primitives=settings.instance_primitives,
                                           scale_factor=settings.instance_scale,
                                           color_source=settings.instance_color_by)
            wm.progress_update(30)
            ifsforge.write_pov_scene(self.filepath, instances, title=system.name, width=self.width,
                                     height=self.height, view=tuple(settings.view))
            wm.progress_update(50)
            if self.render:
                png = os.path.splitext(self.filepath)[0] + ".png"
                ifsforge.render_povray(self.filepath, png, self.width, self.height,
                                       progress=lambda f: wm.progress_update(50 + int(50 * f)) or True)
                image = bpy.data.images.load(png, check_existing=True)
                image.reload()
        except Exception as error:
            report_error(self, error)
            return {'CANCELLED'}
        finally:
            wm.progress_end()
        self.report({'INFO'}, f"wrote {self.filepath}: {len(instances):,} instances")
        return {'FINISHED'}


classes = (IFSFORGE_OT_export_povray,)
