"""ifsforge fit: an IFS whose attractor looks like a target picture or 3D shape (the inverse problem, seed chapter 4).

A separable CMA-ES with restarts searches the maps' Eq. 5 parameters under a collage proxy on a
small raster, polishes each run on the attractor, refines the best on the collage at the
picture's resolution, then climbs the attractor's IoU there; every map stays contractive. The
written system carries render.window and the picture's size, so `ifsforge render SYSTEM.json`
frames it like the target. A color picture (seed Fig. 4.3) gets layout xy+rgb: each map's color
rows are fitted by least squares, one collage per channel. A 3D target (.vdb density or level
set; .obj, .ply, .stl, .off mesh, voxelised) gets an xyz system in the target's coordinates, so
`ifsforge volume SYSTEM.json` frames it where the target lies.
"""
import os
import time

import ifsforge
from ifsforge import cli_common as common
from ifsforge.progress import ProgressBar

AUTO_MAPS = (2, 3, 4, 5, 6, 8)  # what --maps auto tries
AUTO_MAP_COST = 0.01            # IoU a map must buy to be kept under --maps auto
AUTO_PROBE_RESTARTS = 4         # restarts of a count's probe under --maps auto: one of each kind of start
AUTO_PROBE_SHARE = 0.25         # of the time left that a probe may spend under --maps auto with a time limit
AUTO_PATIENCE = 2               # counts in a row that may not pay before --maps auto stops
SHAPE_EXTENSIONS = (".vdb", ".obj", ".ply", ".stl", ".off")  # 3D targets


def register(subparsers):
    # Every default is the core's (FitOptions, Fit3dOptions, ColorFitOptions, VoxelTargetOptions), written once in C++.
    o, o3, color = ifsforge.FitOptions(), ifsforge.Fit3dOptions(), ifsforge.ColorFitOptions()
    p = subparsers.add_parser("fit", help="fit an IFS to a target picture or 3D shape (collage theorem, CMA-ES)",
                              description=__doc__.split("\n\n")[1].replace("\n", " "))
    p.add_argument("target", help="a PNG picture (its shape is the pixels unlike the border; gray: thresholded; "
                   "color: fitted per channel too), or a 3D shape: " + ", ".join(SHAPE_EXTENSIONS))
    p.add_argument("-o", "--output", required=True, help="the system to write (.json)")
    p.add_argument("--maps", default=None, help=f"number of maps (default {o.maps}; 3D {o3.maps}), or 'auto' "
                   "(short fits of %s in turn until %d in a row raise the IoU by less than %g a map, then the full fit "
                   "of the best)" % (", ".join(map(str, AUTO_MAPS)), AUTO_PATIENCE, AUTO_MAP_COST))
    p.add_argument("--time-limit", type=common.float_option(0, 1e9), default=o.time_limit,
                   help="seconds (0: none); a search cut short depends on the machine's speed")
    p.add_argument("--seed", type=common.SEED, default=o.seed)
    p.add_argument("--threads", type=common.THREADS, default=o.threads, help="0: every core (the result does not depend on it)")
    p.add_argument("--restarts", type=common.count_option(10**4), default=None, help=f"CMA-ES runs per map count (default {o.restarts}; 3D {o3.restarts})")
    p.add_argument("--raster", type=common.int_option(8, 4096), default=None,
                   help=f"cells along the long side during the search (default {o.raster}; 3D {o3.raster})")
    p.add_argument("--max-contraction", type=common.float_option(0, 1, low_open=True), default=None,
                   help=f"largest contraction factor of a map (default {o.max_contraction}; 3D {o3.max_contraction}; "
                   f"color maps {color.max_contraction})")
    p.add_argument("--threshold", type=common.float_option(0, 1), default=0.5, help="gray pictures: luminance splitting shape from background")
    no_color = p.add_argument("--no-color", action="store_true", help="color pictures: fit the shape only (layout xy)")
    tolerance = p.add_argument("--color-tolerance", type=common.float_option(0, 1), default=color.tolerance,
                               help="color pictures: a channel difference from the border's color above this is shape")
    common.add_deprecated_alias(p, "--no-colour", no_color)
    common.add_deprecated_alias(p, "--colour-tolerance", tolerance)
    p.add_argument("--voxels", type=common.int_option(4, 4096), default=None,
                   help="3D targets: voxels along the shape's longest side (default: VoxelTargetOptions.resolution)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(run=run)


def fit_best(fit, target, maps, time_limit=None, **options):
    """fit(target, maps=n, ...) for one map count, or for maps='auto' the count chosen by probes:
    short fits (AUTO_PROBE_RESTARTS restarts, without the last search on the IoU) of the counts of
    AUTO_MAPS in turn until AUTO_PATIENCE counts in a row fail to beat the best by AUTO_MAP_COST
    per extra map (a snowflake's structure shows only once its five copies may be placed), then
    the last search on the IoU from the best count's probe (its restarts are not run again). With a
    time limit, the probes and the last search share it (a probe may spend AUTO_PROBE_SHARE of what
    is left). `fit` is ifsforge.fit or ifsforge.fit_3d, `target`
    its positional and keyword target arguments, `options` its options' fields. Returns the result
    dict plus 'maps' (and under 'auto', 'probes': each count tried and its probe's IoU)."""
    args, keywords = target
    if maps != "auto":
        result = fit(*args, **keywords, maps=int(maps), time_limit=time_limit, **options)
        result["maps"] = int(maps)
        return result
    deadline = time.monotonic() + time_limit if time_limit else None
    probe_options = dict(options, restarts=min(options.get("restarts", AUTO_PROBE_RESTARTS), AUTO_PROBE_RESTARTS),
                         final_generations=0)
    probe_options.pop("progress", None)
    probes, chosen, kept, unpaid, start = [], None, None, 0, None
    for n in AUTO_MAPS:
        limit = None
        if deadline is not None:
            left = deadline - time.monotonic()
            if chosen is not None and left <= 0:
                break
            limit = max(left, 1e-3) * AUTO_PROBE_SHARE
        probe = fit(*args, **keywords, maps=n, time_limit=limit, **probe_options)
        probes.append({"maps": n, "iou": probe["iou"]})
        if kept is not None and probe["iou"] - AUTO_MAP_COST * n <= kept - AUTO_MAP_COST * chosen:
            unpaid += 1
            if unpaid == AUTO_PATIENCE:
                break
            continue
        chosen, kept, unpaid, start = n, probe["iou"], 0, probe
    limit = None if deadline is None else max(deadline - time.monotonic(), 1e-3)
    result = fit(*args, **keywords, maps=chosen, time_limit=limit, start=start["system"], **options)
    result["maps"], result["probes"], result["restarts"] = chosen, probes, start["restarts"]
    result["time_limited"] = result["time_limited"] or start["time_limited"]
    return result


def fit_picture(picture, maps, threshold, time_limit=None, **options):
    """fit() of a picture (a bool mask or a picture thresholded at `threshold`): see fit_best."""
    return fit_best(ifsforge.fit, ((picture,), {"threshold": threshold}), maps, time_limit, **options)


def auto_probes(result):
    """The probes of --maps auto for the JSON summary (none for a given count)."""
    return {"probes": result["probes"]} if "probes" in result else {}


def common_options(args, defaults):
    """The options `fit` and `fit_3d` share, each left unset on the command line from `defaults`."""
    given = {"restarts": args.restarts, "raster": args.raster, "max_contraction": args.max_contraction}
    return {"seed": args.seed, "threads": args.threads,
            **{key: getattr(defaults, key) if value is None else value for key, value in given.items()}}


def run_picture(args, bar):
    picture = ifsforge.read_png(args.target)
    color = not args.no_color and ifsforge.has_color(picture)
    # A color picture's shape is what differs from the border's color (a dark blue on black is
    # shape although its luminance is below any threshold); a gray one's, what crosses the threshold.
    shape = ifsforge.color_foreground(picture, args.color_tolerance) if color else picture
    maps = args.maps or str(ifsforge.FitOptions().maps)
    result = fit_picture(shape, maps, args.threshold, time_limit=args.time_limit, progress=bar,
                         **common_options(args, ifsforge.FitOptions()))
    system = result["system"]
    system.name = f"fit of {args.target}"
    collage = ifsforge.collage_distance(system, shape, threshold=args.threshold)
    summary = {"output": args.output, "maps": result["maps"], "iou": result["iou"],
               "collage_distance_pixels": collage["distance_pixels"], "bound_pixels": collage["bound_pixels"],
               "contraction": collage["contraction"], "evaluations": result["evaluations"],
               "restarts": result["restarts"], "time_limited": result["time_limited"], **auto_probes(result)}
    text = (f"{args.output}: {result['maps']} maps, attractor IoU {result['iou']:.3f}, collage distance "
            f"{collage['distance_pixels']:.2f} px (attractor within {collage['bound_pixels']:.2f} px), "
            f"s = {collage['contraction']:.3f}, {result['evaluations']} evaluations")
    if color:
        fitted = ifsforge.fit_color(system, picture, shape, max_contraction=args.max_contraction)  # None: its default
        system = fitted["system"]
        summary["layout"] = "xy+rgb"
        summary["color_collage_error"] = dict(zip("rgb", fitted["collage_error"]))
        text += ", color collage error (RMS) " + " ".join(f"{c} {e:.3f}" for c, e in zip("rgb", fitted["collage_error"]))
    return system, summary, text, result["time_limited"]


def run_shape(args, bar):
    reading = {} if args.voxels is None else {"resolution": args.voxels}
    target = ifsforge.read_voxel_target(args.target, **reading)
    defaults = ifsforge.Fit3dOptions()
    maps = args.maps or str(defaults.maps)
    result = fit_best(ifsforge.fit_3d, ((), target), maps, time_limit=args.time_limit, progress=bar,
                      **common_options(args, defaults))
    system = result["system"]
    system.name = f"fit of {args.target}"
    size = target["voxel_size"]
    shape = target["mask"].shape
    box = list(target["origin"]) + [o + n * size for o, n in zip(target["origin"], shape)]
    iou = volume_iou(system, target["mask"], box, args.threads)
    summary = {"output": args.output, "maps": result["maps"], "iou": iou, "search_iou": result["iou"],
               "proxy": result["proxy"], "voxels": list(shape), "bounds": box,
               "contraction": max(system.contraction_factors()), "evaluations": result["evaluations"],
               "restarts": result["restarts"], "time_limited": result["time_limited"], **auto_probes(result)}
    bounds = " ".join(f"{v:.6g}" for v in box)
    text = (f"{args.output}: {result['maps']} maps, attractor IoU {iou:.3f} on the {'x'.join(map(str, shape))} "
            f"target as `ifsforge volume {args.output} --bounds {bounds} --res {max(shape)}` renders it "
            f"(the search's estimate {result['iou']:.3f}), s = {summary['contraction']:.3f}, "
            f"{result['evaluations']} evaluations")
    return system, summary, text, result["time_limited"]


def volume_iou(system, mask, box, threads):
    """The IoU the user sees: `ifsforge volume` (PRR) on the target's own box and voxel count, whose
    grid is the target's voxel for voxel, against the target."""
    import numpy as np
    volume = ifsforge.render_volume(system, "prr", resolution=max(mask.shape), bounds=box, threads=threads)
    drawn = np.zeros(mask.shape, bool)
    ijk = np.asarray(volume.coords)
    inside = np.all((ijk >= 0) & (ijk < np.asarray(mask.shape)), axis=1)
    drawn[tuple(ijk[inside].T)] = True
    union = np.count_nonzero(drawn | mask)
    return float(np.count_nonzero(drawn & mask) / union) if union else 0.0


def run(args):
    if args.maps is not None and args.maps != "auto":
        try:
            int(args.maps)
        except ValueError:
            raise ifsforge.InputError(f"--maps expects a number or 'auto', got '{args.maps}'") from None
    common.ensure_output_folder(args.output)
    shape = os.path.splitext(args.target)[1].lower() in SHAPE_EXTENSIONS
    bar = ProgressBar("fit", enabled=False if args.json else None)
    try:
        system, summary, text, limited = (run_shape if shape else run_picture)(args, bar)
    except ifsforge.InputError as error:
        raise ifsforge.InputError(f"{args.target}: {error}") from None
    ifsforge.write_json(args.output, system)
    if args.json:
        print(common.to_json(summary))
    else:
        print(text + (" (cut short by --time-limit)" if limited else ""))
    return 0
