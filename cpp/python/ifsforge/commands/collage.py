"""ifsforge collage: how well a system's maps tile a target picture (collage theorem, Eq. 41-42)."""

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser("collage", help="collage distance of a system to a target picture and the "
                                              "bound it gives on the attractor's distance (Eq. 41-42)")
    common.add_system_argument(p)
    p.add_argument("target", help="a PNG picture; its shape is the pixels unlike the border")
    p.add_argument("--threshold", type=common.float_option(0, 1), default=0.5, help="luminance splitting shape from background")
    p.add_argument("--window", type=common.NUMBER, nargs=4, metavar=("XMIN", "YMIN", "XMAX", "YMAX"),
                   help="the plane's rectangle the picture shows (default: the system's render.window, else "
                   "its attractor's frame)")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(run=run)


def run(args):
    system = common.load_system(args.system)
    picture = ifsforge.read_png(args.target)
    try:
        report = ifsforge.collage_distance(system, picture, window=args.window, threshold=args.threshold)
    except ifsforge.InputError as error:
        raise ifsforge.InputError(f"{args.target}: {error}") from None
    if args.json:
        print(common.to_json(report))
        return 0
    print(f"target {args.target}: {report['target_pixels']} pixels on window "
          f"{' '.join(f'{v:g}' for v in report['window'])}; collage {report['collage_pixels']} pixels")
    print(f"collage distance (Eq. 41): {report['distance_pixels']:.3f} px = {report['distance']:.6g}")
    print(f"contraction s = {report['contraction']:.4f}; attractor within eps/(1-s) = "
          f"{report['bound_pixels']:.3f} px = {report['bound']:.6g} of the target (Eq. 42)")
    return 0
