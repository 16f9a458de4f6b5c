"""ifsforge render: a 2D image of a system with any chapter-5 algorithm."""
import ifsforge
from ifsforge import cli_common as common
from ifsforge import distributed
from ifsforge.progress import ProgressBar


def register(subparsers):
    # Every default is the core's (RenderOptions, ToneOptions): written once, in C++.
    o, tone = ifsforge.RenderOptions(), ifsforge.ToneOptions()
    p = subparsers.add_parser("render", help="render a system to a PNG image",
                              description="Render a system to PNG. Defaults come from the system's "
                              "'render' object, then from the options' defaults.")
    common.add_system_argument(p)
    p.add_argument("-o", "--output", required=True, help="PNG file to write")
    p.add_argument("--algorithm", "-a", default=None,
                   help="rendering algorithm (see `ifsforge algorithms`; default chaos)")
    p.add_argument("--size", default=None, help=f"N or WxH pixels (default {o.width})")
    p.add_argument("--iterations", type=common.int_option(0, 10**12), default=o.iterations, help="points for random iteration (0: Eq. 44/45)")
    p.add_argument("--depth", type=common.int_option(0, 64), default=o.depth, help="recursion depth (0: automatic, Eq. 59)")
    p.add_argument("--seed", type=common.SEED, default=o.seed)
    p.add_argument("--threads", type=common.THREADS, default=o.threads, help="0: every core (the image never depends on it)")
    p.add_argument("--mode", default=tone.mode, choices=["auto", "binary", "density", "color", "shaded"],
                   help="binary coverage, log density, the color channels, or a lit z-buffer (3D); "
                   "auto: shaded for 3D, color when the layout has color, else density")
    p.add_argument("--gamma", type=common.float_option(0, 100, low_open=True), default=tone.gamma)
    p.add_argument("--invert", action="store_true", help="dark attractor on white")
    p.add_argument("--bits", type=int, default=8, choices=[8, 16])
    p.add_argument("--points-per-pixel", type=common.float_option(0, 1e6, low_open=True), default=o.points_per_pixel, help="PEPP of Eq. 44")
    p.add_argument("--window", type=common.NUMBER, nargs=4, metavar=("XMIN", "YMIN", "XMAX", "YMAX"))
    p.add_argument("--view", type=common.NUMBER, nargs=2, metavar=("YAW", "PITCH"), help="3D systems: degrees")
    p.add_argument("--reference", help="color-stealing: the picture colors come from")
    p.add_argument("--reference-system", help="color-stealing: the system that walks the picture")
    p.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="an algorithm setting, repeatable (`ifsforge algorithms` lists them)")
    distributed.add_cluster_arguments(p)
    p.set_defaults(run=run)


def run(args):
    system = common.load_system(args.system)
    defaults = system.render_defaults
    algorithm = args.algorithm or defaults.get("algorithm", "chaos")
    width, height = common.parse_size(args.size) if args.size else defaults.get("size", (None, None))
    window = args.window or defaults.get("window")
    view = args.view or defaults.get("view")
    common.ensure_output_folder(args.output)
    extra = {}
    if args.reference:
        extra["reference_image"] = ifsforge.read_png(args.reference)
        if args.reference_system:
            extra["reference_system"] = common.load_system(args.reference_system)
        if not args.algorithm:
            algorithm = "color-stealing"
    with distributed.client_from_args(args) as client:
        raster = distributed.render(
            system, algorithm, client=client, width=width, height=height, window=window, view=view,
            iterations=args.iterations, depth=args.depth, seed=args.seed, threads=args.threads,
            binary=args.mode == "binary", points_per_pixel=args.points_per_pixel,
            progress=ProgressBar(f"render {system.name}"), parameters=common.parse_parameters(args.param), **extra)
    ifsforge.write_png(args.output, raster, args.bits, mode=args.mode, gamma=args.gamma, invert=args.invert)
    print(f"{args.output}: {raster.width}x{raster.height} {algorithm}, {raster.points} points, "
          f"{raster.covered()} pixels covered")
