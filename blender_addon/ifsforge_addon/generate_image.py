"""A 2D rendering of the system (any chapter-5 algorithm) as an image datablock."""
import bpy

import ifsforge

from . import outputs
from .generators import Generator, register_generator


class ImageGenerator(Generator):
    kind = 'IMAGE'
    label = "Image"
    suffix = ".png"
    datablock = "image"

    def draw(self, layout, settings, system):
        layout.prop(settings, "image_size")
        layout.prop(settings, "image_algorithm")
        layout.prop(settings, "image_mode")
        if system is not None and system.spatial_dims == 3:
            layout.prop(settings, "view")

    def work(self, system, settings, path, progress):
        view = settings["view"] if system.spatial_dims == 3 else None
        raster = ifsforge.render(system, settings["image_algorithm"], settings["image_size"], view=view,
                                 seed=settings["seed"], progress=progress)
        ifsforge.write_png(path, raster.to_image(settings["image_mode"]), 16)
        return {"path": path, "summary": f"{raster.width}x{raster.height}, {raster.points:,} points, "
                                         f"{raster.covered():,} pixels covered"}

    def apply(self, context, owner, result, name):
        if owner is None:
            owner = bpy.data.images.load(result["path"], check_existing=False)
            owner.name = name
            owner.use_fake_user = True  # no material uses it yet: keep it when the .blend is saved
        owner.filepath = outputs.stored(result["path"])
        owner.reload()
        return owner


register_generator(ImageGenerator())
