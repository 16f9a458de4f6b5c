#!/usr/bin/python3
"""The volume gallery: every 3D sample system as an OpenVDB volume (.vdb, for Blender's Volume
object), its iso-surface (.glb) and a preview (.png): the voxels themselves, composited front to
back (emission-absorption) in an orthographic view, shaded by depth.

    make(Path("out"))   # writes out/volume/*.vdb, *.glb, *.png and prints one line per item
"""
import math
import sys
import time
from pathlib import Path

import numpy as np

import ifsforge

HERE = Path(__file__).resolve().parent
SYSTEMS = HERE.parent / "systems"
# (sample, resolution, algorithm): the foundation's binary solids and this area's systems.
ITEMS = [
    ("sierpinski_pyramid", 160, "prr"),
    ("volume_sierpinski_pyramid_rgb", 160, "prr"),
    ("menger_sponge", 81, "prr"),
    ("volume_menger_gray", 81, "prr"),
    ("volume_fern_3d", 192, "prr"),
    ("volume_coral_6d", 128, "prr"),
    ("volume_hsi_tower", 160, "prr"),
    ("volume_tetrahedron_alpha", 128, "prr"),
]
PREVIEW = 420          # pixels a side
OPACITY = 0.35         # of one voxel layer
BACKGROUND = (0.08, 0.08, 0.1)
PLAIN = np.array([0.85, 0.75, 0.55])  # colour of binary volumes
ADAPTIVITY = 0.5       # iso-surfaces: merge flat areas (the sponge's faces) into fewer triangles


def view_axes(yaw, pitch):
    """Screen right, screen up and toward-the-viewer axes (the 2D renderer's view convention)."""
    y, p = math.radians(yaw), math.radians(pitch)
    right = np.array([math.cos(y), math.sin(y), 0.0])
    up = np.array([math.sin(p) * math.sin(y), -math.sin(p) * math.cos(y), math.cos(p)])
    toward = np.cross(right, up)
    return right, up, toward


def preview(volume, yaw, pitch, size=PREVIEW):
    """An RGB image of the volume's voxels composited front to back."""
    right, up, toward = view_axes(yaw, pitch)
    positions = volume.positions
    u, v, depth = positions @ right, positions @ up, positions @ toward
    extent = max(u.max() - u.min(), v.max() - v.min()) + 2 * volume.voxel_size
    scale = 0.92 * size / extent
    cx, cy = 0.5 * (u.max() + u.min()), 0.5 * (v.max() + v.min())
    px = ((u - cx) * scale + size / 2).astype(np.int64)
    py = ((cy - v) * scale + size / 2).astype(np.int64)
    attributes = volume.attributes()
    color = attributes["color"] if "color" in attributes else np.tile(PLAIN, (len(volume), 1))
    alpha = np.full(len(volume), OPACITY)
    if "alpha" in attributes:
        alpha = alpha * (0.15 + 0.85 * attributes["alpha"])
    # Depth cue: nearer voxels brighter.
    near = (depth - depth.min()) / max(depth.max() - depth.min(), 1e-12)
    color = color * (0.45 + 0.55 * near)[:, None]
    # Each voxel covers a square of about `scale * voxel_size` pixels.
    foot = max(1, int(math.ceil(scale * volume.voxel_size)))
    dx, dy = np.meshgrid(np.arange(foot), np.arange(foot))
    px = (px[:, None] + dx.ravel()[None, :]).ravel()
    py = (py[:, None] + dy.ravel()[None, :]).ravel()
    keep = (px >= 0) & (px < size) & (py >= 0) & (py < size)
    index = np.repeat(np.arange(len(volume)), foot * foot)[keep]
    pixel = (py * size + px)[keep]
    # Front to back per pixel: transmittance before each voxel = exp(sum of log(1 - a) in front).
    order = np.lexsort((-depth[index], pixel))
    pixel, index = pixel[order], index[order]
    a = alpha[index]
    log_clear = np.log1p(-a)
    running = np.cumsum(log_clear)
    first = np.r_[True, pixel[1:] != pixel[:-1]]
    start = np.maximum.accumulate(np.where(first, np.arange(len(pixel)), 0))
    before = running - log_clear - np.where(start > 0, running[start - 1], 0.0)
    weight = np.exp(before) * a
    image = np.zeros((size * size, 3))
    for c in range(3):
        image[:, c] = np.bincount(pixel, weights=weight * color[index, c], minlength=size * size)
    cover = np.bincount(pixel, weights=weight, minlength=size * size)
    image += (1.0 - cover)[:, None] * np.asarray(BACKGROUND)
    return np.clip(image.reshape(size, size, 3), 0.0, 1.0)


def make(out):
    folder = Path(out) / "volume"
    folder.mkdir(parents=True, exist_ok=True)
    for name, resolution, algorithm in ITEMS:
        system = ifsforge.read_json(str(SYSTEMS / f"{name}.json"))
        view = system.render_defaults.get("view") or (30.0, 20.0)
        start = time.perf_counter()
        volume = ifsforge.render_volume(system, algorithm, resolution)
        seconds = time.perf_counter() - start
        ifsforge.write_vdb(str(folder / f"{name}.vdb"), volume, system=system)
        mesh = ifsforge.volume_to_mesh(volume, adaptivity=ADAPTIVITY)
        ifsforge.write_mesh(str(folder / f"{name}.glb"), mesh["positions"], mesh["triangles"],
                            normals=mesh["normals"], colors=mesh["colors"], name=system.name)
        ifsforge.write_png(str(folder / f"{name}.png"), preview(volume, *view))
        nx, ny, nz = volume.dims
        print(f"  volume/{name:30s} {nx}x{ny}x{nz} {algorithm} depth {volume.depth:2d}: "
              f"{len(volume):>9,} voxels in {seconds:5.2f} s, mesh {len(mesh['triangles']):>9,} triangles")


if __name__ == "__main__":
    make(Path(sys.argv[1] if len(sys.argv) > 1 else "out"))
