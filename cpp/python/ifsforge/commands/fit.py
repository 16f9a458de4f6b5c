"""ifsforge fit: an IFS whose attractor looks like a target picture (the inverse problem, seed chapter 4).

A separable CMA-ES with restarts searches the maps' Eq. 5 parameters under a collage proxy on a
small raster, polishes each run on the attractor, refines the best on the collage at the
picture's resolution, then climbs the attractor's IoU there; every map stays contractive. The
written system carries render.window and the picture's size, so `ifsforge render SYSTEM.json`
frames it like the target.
"""
import json

import ifsforge
from ifsforge import cli_common as common
from ifsforge.progress import ProgressBar

AUTO_MAPS = (2, 3, 4, 5, 6, 8)  # what --maps auto tries
AUTO_MAP_COST = 0.01            # IoU a map must buy to be kept under --maps auto


def register(subparsers):
    o = ifsforge.FitOptions()  # every default is the core's, written once in C++
    p = subparsers.add_parser("fit", help="fit an IFS to a target picture (collage theorem, CMA-ES)",
                              description=__doc__.split("\n\n")[1].replace("\n", " "))
    p.add_argument("target", help="a PNG picture; its shape is the pixels unlike the border (gray: thresholded)")
    p.add_argument("-o", "--output", required=True, help="the system to write (.json)")
    p.add_argument("--maps", default=str(o.maps), help="number of maps, or 'auto' (tries %s)" % ", ".join(map(str, AUTO_MAPS)))
    p.add_argument("--time-limit", type=float, default=o.time_limit,
                   help="seconds (0: none); a search cut short depends on the machine's speed")
    p.add_argument("--seed", type=int, default=o.seed)
    p.add_argument("--threads", type=int, default=o.threads, help="0: every core (the result does not depend on it)")
    p.add_argument("--restarts", type=int, default=o.restarts, help="CMA-ES runs per map count")
    p.add_argument("--raster", type=int, default=o.raster, help="cells along the long side during the search")
    p.add_argument("--max-contraction", type=float, default=o.max_contraction, help="largest contraction factor of a map")
    p.add_argument("--threshold", type=float, default=0.5, help="luminance splitting shape from background")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(run=run)


def fit_picture(picture, maps, threshold, time_limit=None, **options):
    """fit() for one map count, or the best of AUTO_MAPS for maps='auto' (each extra map must
    raise the IoU by AUTO_MAP_COST); `options` are FitOptions fields. Returns the dict of
    ifsforge.fit plus 'maps'."""
    counts = AUTO_MAPS if maps == "auto" else (int(maps),)
    best = None
    for n in counts:
        limit = time_limit / len(counts) if time_limit else time_limit
        result = ifsforge.fit(picture, threshold=threshold, maps=n, time_limit=limit, **options)
        result["maps"] = n
        if best is None or result["iou"] - AUTO_MAP_COST * n > best["iou"] - AUTO_MAP_COST * best["maps"]:
            best = result
    return best


def run(args):
    if args.maps != "auto":
        try:
            int(args.maps)
        except ValueError:
            raise ifsforge.InputError(f"--maps expects a number or 'auto', got '{args.maps}'") from None
    common.ensure_output_folder(args.output)
    picture = ifsforge.read_png(args.target)
    bar = ProgressBar("fit", enabled=False if args.json else None)
    try:
        result = fit_picture(picture, args.maps, args.threshold, time_limit=args.time_limit, seed=args.seed,
                             threads=args.threads, restarts=args.restarts, raster=args.raster,
                             max_contraction=args.max_contraction, progress=bar)
    except ifsforge.InputError as error:
        raise ifsforge.InputError(f"{args.target}: {error}") from None
    system = result["system"]
    system.name = f"fit of {args.target}"
    collage = ifsforge.collage_distance(system, picture, threshold=args.threshold)
    ifsforge.write_json(args.output, system)
    summary = {"output": args.output, "maps": result["maps"], "iou": result["iou"],
               "collage_distance_pixels": collage["distance_pixels"], "bound_pixels": collage["bound_pixels"],
               "contraction": collage["contraction"], "evaluations": result["evaluations"],
               "restarts": result["restarts"], "time_limited": result["time_limited"]}
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"{args.output}: {result['maps']} maps, attractor IoU {result['iou']:.3f}, collage distance "
              f"{collage['distance_pixels']:.2f} px (attractor within {collage['bound_pixels']:.2f} px), "
              f"s = {collage['contraction']:.3f}, {result['evaluations']} evaluations"
              + (" (cut short by --time-limit)" if result["time_limited"] else ""))
    return 0
