"""Generate > Fractal texture: an image compressed to a partitioned IFS code (seed 3.3.2) and
decoded at any resolution into an image datablock. The .pifs code is kept in the cache folder
beside the decoded PNG, so a new resolution is a decode, never a new encode."""
import hashlib

import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, IntProperty, PointerProperty
from bpy.types import Operator, Panel, PropertyGroup

import ifsforge

from . import outputs
from .outputs import CODE_KEY, SIZE_KEY
from .panels import SidebarPanel


class IFSFORGE_PG_fractal_texture(PropertyGroup):
    source: PointerProperty(type=bpy.types.Image, name="Source", description="The image to compress")
    ratio: FloatProperty(name="Ratio", default=50.0, min=2.0, max=1000.0,
                         description="Compression ratio: the code is at most raw bytes / ratio")
    residual: BoolProperty(name="Residual", default=True,
                           description="Also code what the fractal code misses (a DCT residual layer): "
                           "higher quality for the bytes; off: the fractal code alone")
    width: IntProperty(name="Width", default=0, min=0, max=16384,
                       description="Decoded width in pixels (0: the source's)")
    height: IntProperty(name="Height", default=0, min=0, max=16384,
                        description="Decoded height in pixels (0: the source's)")
    result: PointerProperty(type=bpy.types.Image, name="Texture",
                            description="The fractal texture that Decode re-decodes")


def source_pixels(image):
    """The image's RGB (or RGBA when it has alpha) as rows from the top, floats in [0, 1]."""
    width, height = image.size
    if width == 0 or height == 0:
        raise ifsforge.InputError(f"image '{image.name}' has no pixels (is its file missing?)")
    buffer = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(buffer)
    rgba = buffer.reshape(height, width, 4)[::-1]
    keep_alpha = image.alpha_mode != 'NONE' and bool((rgba[..., 3] < 1.0).any())
    return np.ascontiguousarray(rgba if keep_alpha else rgba[..., :3])


def decoded_size(settings, code):
    return (settings.width or code.width, settings.height or code.height)


def decode_to_png(scene, stem, code, size):
    """Decodes `code` at `size` into a PNG of the cache folder; returns its path."""
    path = outputs.path_for(scene, f"{stem}-{size[0]}x{size[1]}", ".png")
    ifsforge.write_png(path, code.decode(size=size))
    return path


def show(image, path, size):
    """Points `image` at `path` (decoded at `size`) and reloads it. The file it showed before stays:
    an undo step may name it (files.py deletes what nothing can name)."""
    image.filepath = outputs.stored(path)
    image[SIZE_KEY] = list(size)
    image.reload()


def decode_again(image):
    """Decodes a fractal texture's stored code again into the file it names (that file is gone);
    returns an error message or ''."""
    try:
        code = ifsforge.read_pifs(bpy.path.abspath(image[CODE_KEY]))
        size = tuple(image.get(SIZE_KEY, (code.width, code.height)))
        path = bpy.path.abspath(image.filepath)
        ifsforge.write_png(path, code.decode(size=size))
        outputs.note(path)
    except (ifsforge.Error, OSError) as error:
        return f"{image.name}: {error}"
    image.reload()
    return ""


class IFSFORGE_OT_fractal_texture(Operator):
    bl_idname = "ifsforge.fractal_texture"
    bl_label = "Generate Fractal Texture"
    bl_description = "Compress the source image to a fractal code and decode it at the chosen size"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        settings = context.scene.ifsforge_fractal_texture
        if settings.source is None:
            self.report({'ERROR'}, "Fractal texture: pick a source image")
            return {'CANCELLED'}
        try:
            pixels = source_pixels(settings.source)
            code = ifsforge.pifs_encode(pixels, ratio=settings.ratio, residual=settings.residual)
            data = code.to_bytes()
            name = f"{settings.source.name} fractal"
            stem = f"{name}-{hashlib.sha1(data).hexdigest()[:12]}"
            code_path = outputs.path_for(context.scene, stem, ".pifs")
            ifsforge.write_pifs(code_path, code)
            png = decode_to_png(context.scene, stem, code, decoded_size(settings, code))
        except ifsforge.Error as error:
            self.report({'ERROR'}, f"Fractal texture: {error}")
            return {'CANCELLED'}
        image = bpy.data.images.load(png, check_existing=False)
        image.name = name
        image.use_fake_user = True  # no material uses it yet: keep it when the .blend is saved
        image.filepath = outputs.stored(png)
        image[CODE_KEY] = outputs.stored(code_path)
        image[SIZE_KEY] = list(image.size)
        settings.result = image
        self.report({'INFO'}, f"{image.name}: {len(data)} bytes ({pixels.size / len(data):.0f}:1), "
                              f"{image.size[0]}x{image.size[1]}")
        return {'FINISHED'}


class IFSFORGE_OT_fractal_texture_decode(Operator):
    bl_idname = "ifsforge.fractal_texture_decode"
    bl_label = "Decode at Size"
    bl_description = "Decode the fractal texture's stored code again at the chosen size (no new encoding)"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        settings = context.scene.ifsforge_fractal_texture
        image = settings.result
        if image is None or CODE_KEY not in image:
            self.report({'ERROR'}, "Fractal texture: generate one first (no image with a stored code)")
            return {'CANCELLED'}
        path = bpy.path.abspath(image[CODE_KEY])
        try:
            code = ifsforge.read_pifs(path)
            stem = f"{image.name}-{hashlib.sha1(code.to_bytes()).hexdigest()[:12]}"
            size = decoded_size(settings, code)
            png = decode_to_png(context.scene, stem, code, size)
        except (ifsforge.Error, OSError) as error:
            self.report({'ERROR'}, f"Fractal texture: {error}")
            return {'CANCELLED'}
        show(image, png, size)
        return {'FINISHED'}


class IFSFORGE_PT_fractal_texture(SidebarPanel, Panel):
    bl_label = "Fractal texture"
    bl_parent_id = "IFSFORGE_PT_generate"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        settings = context.scene.ifsforge_fractal_texture
        layout = self.layout
        layout.use_property_split = True
        layout.template_ID(settings, "source", open="image.open")
        layout.prop(settings, "ratio")
        layout.prop(settings, "residual")
        layout.prop(settings, "width")
        layout.prop(settings, "height")
        layout.operator(IFSFORGE_OT_fractal_texture.bl_idname, icon='TEXTURE')
        if settings.result is not None:
            layout.prop(settings, "result")
            layout.operator(IFSFORGE_OT_fractal_texture_decode.bl_idname, icon='FILE_REFRESH')


classes = (IFSFORGE_PG_fractal_texture, IFSFORGE_OT_fractal_texture, IFSFORGE_OT_fractal_texture_decode,
           IFSFORGE_PT_fractal_texture)


def register_pointers():
    bpy.types.Scene.ifsforge_fractal_texture = PointerProperty(type=IFSFORGE_PG_fractal_texture)


def unregister_pointers():
    del bpy.types.Scene.ifsforge_fractal_texture
