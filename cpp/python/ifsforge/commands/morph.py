"""ifsforge morph: the frames of a morph between two systems (continuity theorem, chapter 4),
as PNG images or as ifsforge/1 JSON systems."""
import os

import numpy as np

import ifsforge
from ifsforge import cli_common as common
from ifsforge import distributed
from ifsforge.progress import ProgressBar


def register(subparsers):
    p = subparsers.add_parser("morph", help="frames of a morph between two systems (PNG or JSON)",
                              description="Interpolate two systems of one layout (Eq. 5 parameters per map) "
                              "and write one frame per step, t = 0 ... 1.")
    p.add_argument("start", help="the system at t = 0 (" + common.SYSTEM_HELP + ")")
    p.add_argument("end", help="the system at t = 1")
    p.add_argument("-o", "--output", required=True, help="folder for the frames (created if missing)")
    p.add_argument("--frames", type=common.int_option(2, 100000), default=24, help="number of frames (>= 2), t = k / (frames - 1)")
    p.add_argument("--prefix", default="morph", help="frame file names: PREFIX_0000.png, ...")
    p.add_argument("--json", action="store_true", help="write the systems as JSON instead of images")
    p.add_argument("--size", default="512", help="N or WxH pixels")
    p.add_argument("--algorithm", "-a", default="chaos")
    p.add_argument("--mode", default="auto", choices=["auto", "binary", "density", "color", "shaded"])
    p.add_argument("--seed", type=common.SEED, default=0)
    p.add_argument("--view", type=common.NUMBER, nargs=2, metavar=("YAW", "PITCH"), help="3D systems: degrees")
    distributed.add_cluster_arguments(p)
    p.set_defaults(run=run)


def frames(start, end, count):
    """The systems at t = k / (count - 1), one at a time; refuses a morph whose intermediate
    systems lose their attractor (the frames already written are then discarded)."""
    if count < 2:
        raise ifsforge.InputError(f"--frames must be at least 2, got {count}")
    for k in range(count):
        system = ifsforge.morph(start, end, k / (count - 1))
        if system.classify() == "divergent":
            raise ifsforge.DivergentSystemError(f"frame {k} (t = {k / (count - 1):.4g}) of the morph has no attractor")
        yield system


def common_window(systems):
    """One window holding every planar frame (5% margin), so the animation does not jump."""
    lo = np.full(2, np.inf)
    hi = np.full(2, -np.inf)
    for system in systems:
        a, b = system.attractor_bounds(1 << 14)
        lo, hi = np.minimum(lo, a[:2]), np.maximum(hi, b[:2])
    pad = 0.05 * np.maximum(hi - lo, 1e-9)
    return (float(lo[0] - pad[0]), float(lo[1] - pad[1]), float(hi[0] + pad[0]), float(hi[1] + pad[1]))


def run(args):
    start, end = common.load_system(args.start), common.load_system(args.end)
    width, height = common.parse_size(args.size)
    with common.staged_folder(args.output) as staging:
        if args.json:
            for k, system in enumerate(frames(start, end, args.frames)):
                ifsforge.write_json(os.path.join(staging, f"{args.prefix}_{k:04d}.json"), system)
            print(f"{args.output}: {args.frames} systems from '{start.name}' to '{end.name}'")
            return 0
        window = common_window(frames(start, end, args.frames)) if start.spatial_dims == 2 else None
        view = (args.view or start.render_defaults.get("view")) if start.spatial_dims == 3 else None
        bar = ProgressBar(f"morph {start.name} -> {end.name}")
        paths = [os.path.join(staging, f"{args.prefix}_{k:04d}.png") for k in range(args.frames)]
        with distributed.client_from_args(args) as client:
            if client is not None:  # one task per frame, each written by its worker
                distributed.render_frames(client, zip(frames(start, end, args.frames), paths), args.algorithm,
                                          args.mode, progress=bar, width=width, height=height, window=window,
                                          view=view, seed=args.seed, binary=args.mode == "binary")
        for k, system in enumerate(frames(start, end, args.frames) if client is None else []):
            def progress(fraction, k=k):
                return bar((k + fraction) / args.frames)
            raster = ifsforge.render(system, args.algorithm, width, height, window=window, view=view, seed=args.seed,
                                     binary=args.mode == "binary", progress=progress)
            ifsforge.write_png(paths[k], raster.to_image(args.mode))
    print(f"{args.output}: {args.frames} frames from '{start.name}' to '{end.name}' ({width}x{height})")
    return 0
