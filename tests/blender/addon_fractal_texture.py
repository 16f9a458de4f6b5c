"""Inside Blender: Generate > Fractal texture compresses an image datablock to a .pifs code in
the cache folder (within the ratio's budget), shows it decoded as an image datablock close to
the source, decodes it again at another size without encoding again, and reports bad input."""
import os
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, enable_addon, expect_report  # noqa: E402

args = arguments()
OUT = Path(args.out) / "fractal_texture"
OUT.mkdir(parents=True, exist_ok=True)
enable_addon(args.python_path)

import ifsforge  # noqa: E402

checks = Checks()
scene = bpy.context.scene
scene.ifsforge.cache_folder = str(OUT / "cache")
settings = scene.ifsforge_fractal_texture
W, H = 96, 64


def textured():
    y, x = np.mgrid[0:H, 0:W].astype(np.float32)
    rgb = [0.5 + 0.3 * np.sin(x / (6 + c)) * np.cos(y / 9) + 0.1 * np.sin((x + 2 * y) / 4 + c) for c in range(3)]
    return np.round(np.clip(np.stack(rgb + [np.ones_like(x)], axis=-1), 0, 1) * 255) / 255


def pixels(image):
    w, h = image.size
    buffer = np.empty(w * h * 4, np.float32)
    image.pixels.foreach_get(buffer)
    return buffer.reshape(h, w, 4)[::-1]


def check_refuses_without_source():
    settings.source = None
    expect_report(lambda: bpy.ops.ifsforge.fractal_texture(), "pick a source image")
    expect_report(lambda: bpy.ops.ifsforge.fractal_texture_decode(), "generate one first")


def check_generate():
    source = bpy.data.images.new("stone", W, H)
    truth = textured()
    source.pixels.foreach_set(truth[::-1].ravel())
    settings.source = source
    settings.ratio = 20
    assert bpy.ops.ifsforge.fractal_texture() == {'FINISHED'}
    image = settings.result
    assert image is not None and image.name == "stone fractal", image
    assert tuple(image.size) == (W, H), tuple(image.size)
    code_path = bpy.path.abspath(image["ifsforge_pifs"])
    assert os.path.isfile(code_path) and code_path.startswith(str(OUT / "cache")), code_path
    assert os.path.getsize(code_path) <= W * H * 3 / 20
    error = pixels(image)[..., :3] - truth[..., :3]
    psnr = 10 * np.log10(1 / np.mean(error ** 2))
    assert psnr > 25, psnr
    checks.values["generated_psnr"] = float(psnr)


def check_decode_at_another_size():
    image = settings.result
    code_path = bpy.path.abspath(image["ifsforge_pifs"])
    stamp = os.stat(code_path).st_mtime_ns
    first_png = bpy.path.abspath(image.filepath)
    settings.width, settings.height = 3 * W, 3 * H
    assert bpy.ops.ifsforge.fractal_texture_decode() == {'FINISHED'}
    assert tuple(image.size) == (3 * W, 3 * H), tuple(image.size)
    assert os.stat(code_path).st_mtime_ns == stamp  # the code was read, not written again
    assert os.path.exists(first_png)  # the previous decode's file stays: an undo step may name it
    on_disk = ifsforge.read_png(bpy.path.abspath(image.filepath))
    assert on_disk.shape == (3 * H, 3 * W, 3), on_disk.shape
    # The 3x decode, averaged back down, is the 1x decode.
    small = ifsforge.read_pifs(code_path).decode()
    averaged = on_disk.reshape(H, 3, W, 3, 3).mean(axis=(1, 3))
    assert 10 * np.log10(1 / np.mean((averaged - small) ** 2)) > 28


def check_missing_code_reported():
    image = settings.result
    os.remove(bpy.path.abspath(image["ifsforge_pifs"]))
    expect_report(lambda: bpy.ops.ifsforge.fractal_texture_decode(), "cannot open")


checks.run("refuses_without_source", check_refuses_without_source)
checks.run("generate", check_generate)
checks.run("decode_at_another_size", check_decode_at_another_size)
checks.run("missing_code_reported", check_missing_code_reported)
checks.finish()
