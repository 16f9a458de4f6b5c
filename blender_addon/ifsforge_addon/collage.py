"""The design's collage distance to a target picture (seed chapter 4, Eq. 41-42), kept current
as the maps are edited: the picture is shrunk to a small raster and prepared once
(ifsforge.CollageTarget keeps the distance transform to it), so each edit only lays the maps'
copies of it and measures their distance. Also the overlay the viewport draws behind the 2D
preview: the picture on its window and each map's copy of the window as a quadrilateral."""
import time

import numpy as np

import ifsforge

from . import state

# The prepared target: key (image, its size and update count, raster, threshold) -> CollageTarget.
_prepared = {"key": None, "target": None}


def picture(image, raster):
    """The image datablock's pixels as an (h, w, channels) float array, top row first, shrunk
    (nearest pixel) so that its long side has at most `raster` pixels."""
    width, height = image.size
    if width < 1 or height < 1:
        raise ifsforge.InputError(f"the image '{image.name}' has no pixels (is its file missing?)")
    channels = image.channels
    buffer = np.empty(width * height * channels, np.float32)
    image.pixels.foreach_get(buffer)
    pixels = buffer.reshape(height, width, channels)[::-1]  # Blender stores the bottom row first
    step = max(width, height) / raster
    if step > 1:
        rows = (np.arange(int(height / step)) * step).astype(int)
        cols = (np.arange(int(width / step)) * step).astype(int)
        pixels = pixels[rows][:, cols]
    return np.ascontiguousarray(pixels)


def prepared(settings):
    """The CollageTarget of the settings' image (rebuilt only when the image or the raster changes)."""
    image = settings.image
    key = (image.name, tuple(image.size), image.is_dirty, settings.raster, settings.threshold)
    if _prepared["key"] != key:
        target = ifsforge.CollageTarget(picture(image, settings.raster), threshold=settings.threshold)
        _prepared.update(key=key, target=target)
    return _prepared["target"]


def refresh(context):
    """Recomputes the shown collage distance of the edited system (property update callbacks
    call this; without a target it costs nothing)."""
    settings = context.scene.ifsforge.collage
    if settings.image is None:
        return
    start = time.perf_counter()
    try:
        _, pg, _ = state.target(context)
        system = state.system_of(pg)
        if system.spatial_dims != 2:
            raise ifsforge.InputError("the collage distance is for planar (xy) systems")
        report = prepared(settings).distance(system, window=tuple(settings.window))
        settings.distance_pixels = report["distance_pixels"]
        settings.distance = report["distance"]
        settings.bound = report["bound"] if np.isfinite(report["bound"]) else -1.0
        settings.error = ""
    except ifsforge.Error as error:
        settings.distance_pixels = settings.distance = settings.bound = -1.0
        settings.error = str(error)
    settings.seconds = time.perf_counter() - start


def outlines(system, window):
    """Per map, the corners (x, y, 0) of its copy of the window rectangle: where the map puts the
    target (the collage's pieces, drawn as quadrilaterals)."""
    xmin, ymin, xmax, ymax = window
    corners = np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
    quads = []
    for m in system.maps:
        matrix, offset = np.asarray(m.matrix)[:2, :2], np.asarray(m.offset)[:2]
        xy = corners @ matrix.T + offset
        quads.append([(float(x), float(y), 0.0) for x, y in xy])
    return quads


def clear():
    _prepared.update(key=None, target=None)
