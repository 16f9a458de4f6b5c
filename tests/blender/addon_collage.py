"""Inside Blender: a target picture for the 2D design (an image datablock or a file), the collage
distance (Eq. 41-42) the panel shows, kept current by the maps' update callbacks and equal to
ifsforge.collage_distance for the same system and target, and the overlay's copies of the window."""
import statistics
import sys
from pathlib import Path

import bpy
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from addon_harness import Checks, arguments, close, enable_addon  # noqa: E402

args = arguments()
OUT = Path(args.out)
enable_addon(args.python_path)

import ifsforge  # noqa: E402

from ifsforge_addon import collage, state  # noqa: E402

checks = Checks()
scene = bpy.context.scene
design = scene.ifsforge.system
settings = scene.ifsforge.collage
SIZE = 160


def sierpinski_picture():
    """The Sierpinski triangle drawn on [0, 1]^2 at SIZE pixels, white on black (h, w)."""
    system = ifsforge.load(str(Path(__file__).resolve().parents[2] / "samples" / "systems" / "sierpinski_triangle.json"))
    mask = np.asarray(ifsforge.render(system, "chaos", SIZE, SIZE, binary=True, window=[0, 0, 1, 1]).mask, bool)
    return mask.astype(np.float32)


def expected():
    """What the panel must show: ifsforge.collage_distance on the same small raster and window."""
    return ifsforge.collage_distance(state.system_of(design), collage.picture(settings.image, settings.raster),
                                     window=tuple(settings.window), threshold=settings.threshold)


def target_from_datablock():
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    picture = sierpinski_picture()
    image = bpy.data.images.new("target", SIZE, SIZE)
    rgba = np.ones((SIZE, SIZE, 4), np.float32)
    rgba[..., :3] = picture[..., None]
    image.pixels.foreach_set(rgba[::-1].ravel())  # Blender's rows run bottom to top
    settings.window = (0.0, 0.0, 1.0, 1.0)
    assert settings.distance_pixels == -1.0  # nothing computed before a target is set
    settings.image = image  # the update callback computes it
    assert settings.error == "", settings.error
    report = expected()
    assert collage.picture(image, settings.raster).shape[:2] == (96, 96)  # the small raster
    close(settings.distance_pixels, report["distance_pixels"], 1e-5)
    close(settings.distance, report["distance"], 1e-6)
    # The system drawn to the picture tiles it: the collage is within a couple of pixels.
    assert settings.distance_pixels < 3, settings.distance_pixels
    checks.values["exact_distance_pixels"] = settings.distance_pixels


def edits_update_the_distance():
    before = settings.distance_pixels
    design.maps[0].translation = (0.12, 0.05, 0.0)  # a map edit: the callback recomputes
    report = expected()
    assert settings.distance_pixels != before
    close(settings.distance_pixels, report["distance_pixels"], 1e-5)
    close(settings.bound, report["bound"], 1e-5)
    assert settings.distance_pixels > 5  # the copy moved by 0.12 of the picture's 96 pixels
    design.maps[1].scale = (0.4, 0.45, 1.0)
    close(settings.distance_pixels, expected()["distance_pixels"], 1e-5)
    # Each update is cheap: the target's distance transform is prepared once.
    times = []
    for k in range(30):
        design.maps[2].translation = (0.25 + 0.002 * k, 0.5, 0.0)
        times.append(settings.seconds)
        close(settings.distance_pixels, expected()["distance_pixels"], 1e-5)
    checks.values["collage_update_ms_median"] = 1e3 * statistics.median(times)
    assert statistics.median(times) < 0.05, times


def outlines_are_the_copies_of_the_window():
    quads = collage.outlines(state.system_of(design), (0.0, 0.0, 1.0, 1.0))
    assert len(quads) == 3
    # Map 0 is x/2 + (0.12, 0.05): the unit square's copy.
    close(quads[0], [(0.12, 0.05, 0), (0.62, 0.05, 0), (0.62, 0.55, 0), (0.12, 0.55, 0)], 1e-6)


def target_from_file():
    path = OUT / "collage_target.png"
    ifsforge.write_png(str(path), sierpinski_picture())
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    settings.filepath = str(path)
    assert settings.image is not None and Path(bpy.path.abspath(settings.image.filepath)).name == path.name
    close(settings.distance_pixels, expected()["distance_pixels"], 1e-5)
    assert settings.distance_pixels < 3


def three_d_systems_are_refused():
    bpy.ops.ifsforge.load_preset(preset="sierpinski_tetrahedron.json")
    assert "planar" in settings.error and settings.distance_pixels == -1.0
    bpy.ops.ifsforge.load_preset(preset="sierpinski_triangle.json")
    assert settings.error == ""


checks.run("target_from_datablock", target_from_datablock)
checks.run("edits_update_the_distance", edits_update_the_distance)
checks.run("outlines_are_the_copies_of_the_window", outlines_are_the_copies_of_the_window)
checks.run("target_from_file", target_from_file)
checks.run("three_d_systems_are_refused", three_d_systems_are_refused)
checks.finish()
