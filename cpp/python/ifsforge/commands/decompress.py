"""ifsforge decompress: a .pifs code decoded to PNG at any resolution (seed 3.3.2.2)."""
import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser(
        "decompress", help="decode a .pifs code to PNG at any size (fractal super-resolution)",
        description="Baharav's hierarchical decoding: the fixed point of the coarsest level, then one pass "
        "per doubling; sizes between powers of two are area-resampled. --decoder iterative iterates at "
        "the output size instead (the reference).")
    o = ifsforge.PifsDecodeOptions()
    p.add_argument("input", help="a .pifs file")
    p.add_argument("-o", "--output", required=True, help="the PNG to write")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--scale", type=common.float_option(0, 1024, low_open=True), default=o.scale, help="output size = image size x S (default %(default)s)")
    size.add_argument("--size", type=common.count_option(65535), nargs=2, metavar=("W", "H"), help="output size in pixels")
    p.add_argument("--iterations", type=common.int_option(0, 10**6), default=o.iterations,
                   help="fixed-point iterations (coarsest level, or every level with --decoder iterative); "
                   "0: the default")
    p.add_argument("--decoder", choices=ifsforge.choices["decoder"], default=o.decoder)
    p.add_argument("--no-deblock", action="store_true", help="skip the range-block edge filter")
    p.add_argument("--zoom", choices=ifsforge.choices["zoom"], default=o.zoom,
                   help="above 1x: hybrid (default) mixes a share of the fractal detail into the bicubic "
                   "upscale of the 1x decode and back-projects it toward that decode; fractal is the plain "
                   "fractal decode at the output size")
    p.add_argument("--bits", type=int, choices=[8, 16], default=8, help="PNG bits per sample")
    p.add_argument("--threads", type=common.THREADS, default=o.threads, help="0: every core (the image never depends on it)")
    p.set_defaults(run=run)


def run(args):
    common.ensure_output_folder(args.output)
    if args.iterations < 0:
        raise ifsforge.InputError("--iterations must be >= 0")
    if args.size and min(args.size) < 1:
        raise ifsforge.InputError("--size expects two positive integers W H")
    code = ifsforge.read_pifs(args.input)
    image = code.decode(scale=args.scale, size=tuple(args.size) if args.size else None, decoder=args.decoder,
                        iterations=args.iterations, deblock=not args.no_deblock, zoom=args.zoom,
                        threads=args.threads)
    ifsforge.write_png(args.output, image, args.bits)
    print(f"{args.output}: {image.shape[1]}x{image.shape[0]} from {code.width}x{code.height}")
    return 0
