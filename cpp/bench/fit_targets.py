"""Benchmark of `ifsforge fit`: held-out classic attractors, a natural silhouette, colour
pictures and 3D shapes.

Each 2D target is a 256-pixel picture (the attractors rendered by the chaos game, skimage's horse
as it is); the fit runs with a 60 s time limit (times --time-scale) on the given threads. Prints, per target, the
IoU of the fitted attractor with the target, the Hausdorff distance (Eq. 12, pixels) between
the fitted attractor drawn at the target's size and the target, the collage distance
(Eq. 41) and the time. Colour targets (the colour samples drawn as `render` draws them) add the
mean colour error per pixel both cover and the colour collage error (RMS per channel, seed
Fig. 4.3); 3D targets (3D samples as 64^3 .vdb volumes, one also as a voxelised mesh) get 120 s
and report the IoU of the fitted attractor's volume (`volume` on the target's box) with the target.
With --rotated it fits instead held-out rotated systems (a spiral, two dragons, a leaf, a
snowflake) and drawn silhouettes (a letter, a tree) with default options but the map count (no
time limit), once with the right count and once by `--maps auto`, and writes them as a section of
their own: IoU, Hausdorff distance, wall and CPU seconds (all threads; the CPU time is the fair
measure on a shared machine), and auto's count, IoU, times and CPU time over the right count's.
Run: PYTHONPATH=build/python python3 cpp/bench/fit_targets.py [--threads 2] [--time-scale 1] [--rotated [--jobs N]]
"""
import argparse
import json
import os
import pathlib
import sys
import tempfile
import time

import numpy as np

import ifsforge

TIME_LIMIT = 60.0        # seconds per 2D fit (classic, colour)
SHAPE_TIME_LIMIT = 120.0  # seconds per 3D fit

CLASSIC = {
    # name: (maps, JSON maps) -- none of them is a sample system the fit could have seen.
    "sierpinski": (3, [{"scale": 0.5, "translation": [0, 0]}, {"scale": 0.5, "translation": [0.5, 0]},
                       {"scale": 0.5, "translation": [0.25, 0.5]}]),
    "four-corner dust": (4, [{"scale": 0.4, "translation": [x, y]} for x in (0, 0.6) for y in (0, 0.6)]),
    "dragon": (2, [{"matrix": [[0.5, -0.5], [0.5, 0.5]], "offset": [0, 0]},
                   {"matrix": [[-0.5, -0.5], [0.5, -0.5]], "offset": [1, 0]}]),
}


def similarity(scale, degrees, offset, mirror=False):
    """The JSON map x -> scale R(degrees) x + offset (mirrored in x first)."""
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    k = -1 if mirror else 1
    return {"matrix": [[scale * c * k, -scale * s], [scale * s * k, scale * c]], "offset": list(offset)}


def ring(count, radius, scale, degrees):
    """`count` copies on a circle, each turned with its place (snowflakes)."""
    return [similarity(scale, degrees + 360 * k / count, (radius * np.cos(2 * np.pi * k / count),
                                                         radius * np.sin(2 * np.pi * k / count))) for k in range(count)]


GOLDEN = 0.7427429446  # (1/phi)^(1/phi): the golden dragon's ratio
ROTATED = {
    # name: JSON maps -- rotated systems held out from the tests (the spiral 0.88·R(28°)x, 0.28x + (1, 0) first).
    "spiral": [similarity(0.88, 28, (0, 0)), similarity(0.28, 0, (1, 0))],
    "golden dragon": [similarity(GOLDEN, 32.893818, (0, 0)), similarity(GOLDEN ** 2, 133.774435, (1, 0))],
    "terdragon": [similarity(3 ** -0.5, -30, (0, 0)), similarity(3 ** -0.5, 90, (0.5, -0.5 / 3 ** 0.5)),
                  similarity(3 ** -0.5, -30, (0.5, 0.5 / 3 ** 0.5))],
    "leaf": [similarity(0.62, 0, (0, 0.38)), similarity(0.45, 48, (0.04, 0.12)), similarity(0.45, -48, (-0.04, 0.12)),
             {"matrix": [[0.04, 0], [0, 0.32]], "offset": [0, 0]}],
    "snowflake": ring(4, 0.62, 0.34, 15) + [similarity(0.4, 45, (0, 0))],
}


def classic_target(maps, size=256):
    system = ifsforge.parse_json(json.dumps({"format": "ifsforge/1", "name": "target", "layout": "xy",
                                             "maps": maps}))
    return np.asarray(ifsforge.render(system, "chaos", size, size, binary=True).mask, bool)


def horse_target():
    import skimage.data
    horse = ~skimage.data.horse()  # skimage's horse is False on True: the shape is the False pixels
    # 256 pixels along the long side, like the other targets (nearest neighbour).
    h, w = horse.shape
    side = 256 / max(h, w)
    rows = (np.arange(int(h * side)) / side).astype(int)
    cols = (np.arange(int(w * side)) / side).astype(int)
    return horse[rows][:, cols]


def rotated_targets():
    return [(name, classic_target(maps), len(maps)) for name, maps in ROTATED.items()]


def letter_target(text="R", size=256):
    """A letter drawn in DejaVu Sans Bold, 256 pixels tall, with a margin."""
    from PIL import Image, ImageDraw, ImageFont
    font = ImageFont.truetype("/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf", int(size * 0.9))
    picture = Image.new("L", (size, size), 0)
    ImageDraw.Draw(picture).text((size // 2, size // 2), text, fill=255, font=font, anchor="mm")
    return np.asarray(picture) > 127


def tree_target(size=256):
    """A drawn tree: a trunk, two boughs and a round crown (skimage.draw)."""
    import skimage.draw
    mask = np.zeros((size, size), bool)
    s = size / 256
    for rows, cols in (([250, 250, 120, 120], [112, 144, 138, 118]),      # trunk
                       ([150, 140, 80, 90], [125, 135, 60, 50]),          # left bough
                       ([150, 140, 70, 80], [131, 121, 190, 200])):       # right bough
        rr, cc = skimage.draw.polygon(np.array(rows) * s, np.array(cols) * s, mask.shape)
        mask[rr, cc] = True
    for r, c, radius in ((80, 128, 60), (95, 70, 35), (85, 190, 38)):
        rr, cc = skimage.draw.disk((r * s, c * s), radius * s, shape=mask.shape)
        mask[rr, cc] = True
    return mask


def silhouette_targets():
    # A silhouette has no right count: the letter's is the best of 4, 6 and 8 maps measured.
    return [("letter R", letter_target(), 6), ("tree", tree_target(), 4)]


def targets():
    out = [(name, classic_target(maps), n) for name, (n, maps) in CLASSIC.items()]
    out.append(("horse", horse_target(), 10))
    return out


def drawn(system, shape):
    """The fitted attractor drawn by `render` at the target's size on its render.window."""
    raster = ifsforge.render(system, "chaos", shape[1], shape[0], binary=True,
                             window=system.render_defaults["window"])
    return np.asarray(raster.mask, bool)


def evaluate(name, target, maps, threads=2, seed=0, time_limit=TIME_LIMIT):
    start, cpu = time.perf_counter(), time.process_time()
    if maps == "auto":
        import ifsforge.commands.fit as fit_command
        result = fit_command.fit_picture(target, "auto", 0.5, time_limit=time_limit, seed=seed, threads=threads)
        maps = result["maps"]
    else:
        result = ifsforge.fit(target, maps=maps, time_limit=time_limit, seed=seed, threads=threads)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    system = result["system"]
    picture = drawn(system, target.shape)
    iou = float((picture & target).sum() / (picture | target).sum())
    return {"target": name, "maps": maps, "iou": iou, "hausdorff_pixels": ifsforge.hausdorff_distance(picture, target),
            "collage_pixels": ifsforge.collage_distance(system, target)["distance_pixels"], "seconds": seconds, "cpu": cpu,
            "time_limited": result["time_limited"], "system": system, "fit": picture}


SAMPLES = pathlib.Path(__file__).resolve().parents[2] / "samples" / "systems"
COLOUR = {"colour sierpinski": ("colour5d_sierpinski_rgb.json", 3), "colour dragon": ("colour5d_dragon_rgb.json", 2)}
SHAPES = {"tetrahedron (.vdb)": ("sierpinski_tetrahedron.json", 4, ".vdb"),
          "tetrahedron (.ply mesh)": ("sierpinski_tetrahedron.json", 4, ".ply"),
          "3D fern (.vdb)": ("volume_fern_3d.json", 4, ".vdb")}


def color_targets(size=256):
    """(name, RGB picture drawn as `render` draws the sample, maps)."""
    out = []
    for name, (file, maps) in COLOUR.items():
        system = ifsforge.load(str(SAMPLES / file))
        d = system.render_defaults
        raster = ifsforge.render(system, d.get("algorithm", "chaos"), size, size, window=d.get("window"))
        out.append((name, np.ascontiguousarray(np.asarray(raster.to_image(), np.float32)[..., :3]), maps))
    return out


def evaluate_color(name, picture, maps, threads=2, seed=0, time_limit=TIME_LIMIT):
    start = time.perf_counter()
    shape = ifsforge.color_foreground(picture)
    result = ifsforge.fit(shape, maps=maps, time_limit=time_limit, seed=seed, threads=threads)
    coloured = ifsforge.fit_color(result["system"], picture, shape)
    seconds = time.perf_counter() - start
    system = coloured["system"]
    h, w = shape.shape
    drawn = np.asarray(ifsforge.render(system, "chaos", w, h, window=system.render_defaults["window"]).to_image(),
                       np.float32)[..., :3]
    covered = drawn.max(axis=2) > 0
    both = covered & shape
    return {"target": name, "maps": maps, "iou": float(both.sum() / (covered | shape).sum()),
            "color_error": float(np.abs(drawn - picture)[both].mean()), "collage_error": coloured["collage_error"],
            "seconds": seconds, "time_limited": result["time_limited"], "system": system, "fit": drawn}


def shape_target(file, extension, folder, resolution=64):
    """The sample's volume as a .vdb, or its iso-surface as a mesh, read back as fit reads it."""
    system = ifsforge.load(str(SAMPLES / file))
    volume = ifsforge.render_volume(system, "prr", resolution=resolution)
    path = os.path.join(folder, pathlib.Path(file).stem + extension)
    if extension == ".vdb":
        ifsforge.write_vdb(path, volume)
    else:
        ifsforge.write_mesh(path, **{k: v for k, v in ifsforge.volume_to_mesh(volume).items()
                                      if k in ("positions", "triangles")})
    return ifsforge.read_voxel_target(path, resolution=resolution)


def occupancy(system, target):
    """The fitted attractor as `volume` draws it (prr) on the target's own voxels."""
    size, (nx, ny, nz) = target["voxel_size"], target["mask"].shape
    box = list(target["origin"]) + [o + n * size for o, n in zip(target["origin"], (nx, ny, nz))]
    volume = ifsforge.render_volume(system, "prr", resolution=max(nx, ny, nz), bounds=box)
    return volume.to_dense("occupancy")[:nx, :ny, :nz] > 0


def evaluate_3d(name, target, maps, threads=2, seed=0, time_limit=SHAPE_TIME_LIMIT):
    start = time.perf_counter()
    result = ifsforge.fit_3d(**target, maps=maps, time_limit=time_limit, seed=seed, threads=threads)
    seconds = time.perf_counter() - start
    drawn = occupancy(result["system"], target)
    mask = target["mask"]
    return {"target": name, "maps": maps, "iou": float((drawn & mask).sum() / (drawn | mask).sum()),
            "fit_iou": result["iou"], "seconds": seconds, "time_limited": result["time_limited"],
            "system": result["system"], "fit": drawn, "voxels": mask.shape}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--time-scale", type=float, default=1.0,
                        help="multiplies every time limit (a loaded machine gives a fit less CPU per wall second; "
                        "0: no limit, the CPU time then measures)")
    parser.add_argument("--only", default=None, metavar="NAME,...",
                        help="only these targets (names as printed); with --rotated or the planar classic ones")
    parser.add_argument("--rotated", action="store_true",
                        help="only the rotated systems and drawn silhouettes, right count and --maps auto (own section)")
    parser.add_argument("--jobs", type=int, default=1,
                        help="with --rotated, fits run at once, each in its own process (a shared machine gives "
                        "each its share; the CPU seconds stay each fit's own)")
    import results  # beside this script; imported here, as the galleries import this module without it
    results.add_argument(parser)
    args = parser.parse_args()
    if args.rotated:
        with results.Section("fit_targets.py --rotated", args.results,
                             "Fitting rotated systems and drawn silhouettes (fit_targets.py --rotated)",
                             preformatted=True) as out:
            rotated(args, out)
        return
    with results.Section("fit_targets.py", args.results,
                         "Fitting (fit_targets.py)",
                         preformatted=True) as out:
        report(args, out)


def chosen(targets, only):
    """The (name, target, maps) of `targets` named in `only` (comma-separated; None: all)."""
    return targets if only is None else [t for t in targets if t[0] in only.split(",")]


def report(args, out):
    scale = args.time_scale
    out.print(f"{'target':18} {'maps':>4} {'IoU':>6} {'Hausdorff px':>12} {'collage px':>10} {'time s':>7} {'CPU s':>7}")
    for name, target, maps in chosen(targets(), args.only):
        r = evaluate(name, target, maps, args.threads, args.seed, time_limit=TIME_LIMIT * scale)
        out.print(f"{name:18} {maps:4d} {r['iou']:6.3f} {r['hausdorff_pixels']:12.2f} {r['collage_pixels']:10.2f} "
                  f"{r['seconds']:7.1f} {r['cpu']:7.1f}" + (" (time limit)" if r["time_limited"] else ""))
    if args.only is not None:
        return
    out.print(f"\n{'colour target':18} {'maps':>4} {'IoU':>6} {'colour error':>12} {'collage RMS r g b':>20} {'time s':>7}")
    for name, picture, maps in color_targets():
        r = evaluate_color(name, picture, maps, args.threads, args.seed, time_limit=TIME_LIMIT * scale)
        out.print(f"{name:18} {maps:4d} {r['iou']:6.3f} {r['color_error']:12.4f} "
                  f"{' '.join(f'{e:.3f}' for e in r['collage_error']):>20} {r['seconds']:7.1f}")
    out.print(f"\n{'3D target':24} {'maps':>4} {'IoU':>6} {'fit IoU':>7} {'time s':>7}")
    with tempfile.TemporaryDirectory() as folder:
        for name, (file, maps, extension) in SHAPES.items():
            r = evaluate_3d(name, shape_target(file, extension, folder), maps, args.threads, args.seed,
                            time_limit=SHAPE_TIME_LIMIT * scale)
            out.print(f"{name:24} {maps:4d} {r['iou']:6.3f} {r['fit_iou']:7.3f} {r['seconds']:7.1f}"
                      + (" (time limit)" if r["time_limited"] else ""))


def evaluate_untimed(job):
    """evaluate() without a time limit of (name, target, maps, threads, seed), less what does not
    pickle: a job of rotated()'s process pool, in a session of its own: a kernel that shares the
    CPU between sessions (autogroup) would give all the pool's fits together one session's share."""
    if os.getsid(0) != os.getpid():
        os.setsid()
    r = evaluate(*job[:3], job[3], job[4], time_limit=0)
    r = {k: v for k, v in r.items() if k not in ("system", "fit")}
    print(f"fit_targets.py: {r}", file=sys.stderr, flush=True)  # each fit as it ends: a long run's partial results
    return r


def rotated(args, out):
    """Rotated systems and drawn silhouettes with the right count of maps and by --maps auto;
    default options (no time limit) but the maps. With --jobs, that many fits run at once, each
    in its own process (its CPU time is its own)."""
    out.print(f"{'rotated target':14} {'maps':>4} {'IoU':>6} {'Hausdorff px':>12} {'time s':>7} {'CPU s':>7}"
              f" {'auto maps':>9} {'auto IoU':>8} {'auto s':>7} {'auto CPU s':>10} {'CPU ratio':>9}")
    import concurrent.futures
    import multiprocessing
    fits = chosen(rotated_targets() + silhouette_targets(), args.only)
    jobs = [(name, target, count, args.threads, args.seed) for name, target, maps in fits for count in (maps, "auto")]
    with concurrent.futures.ProcessPoolExecutor(args.jobs, mp_context=multiprocessing.get_context("spawn")) as pool:
        done = list(pool.map(evaluate_untimed, jobs))
    for (name, target, maps), r, a in zip(fits, done[0::2], done[1::2]):
        out.print(f"{name:14} {maps:4d} {r['iou']:6.3f} {r['hausdorff_pixels']:12.2f} {r['seconds']:7.1f} "
                  f"{r['cpu']:7.1f} {a['maps']:9d} {a['iou']:8.3f} {a['seconds']:7.1f} {a['cpu']:10.1f} "
                  f"{a['cpu'] / r['cpu']:9.2f}")


if __name__ == "__main__":
    main()
