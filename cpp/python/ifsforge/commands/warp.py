"""ifsforge warp: a picture carried from one attractor onto another by fractal tops (seed 3.3.5).

The picture is laid on F's frame (its render.window, else its attractor's); every pixel of G's
attractor takes the color at phi_F(tau_G(pixel)), the fractal homeomorphism between attractors
with the same code space (Fig. 3.16). With --frames K, G moves from F to G (continuity theorem:
the morph's parameters interpolated) and DIR/frame_0000.png ... are written (Fig. 3.15).
"""
import os

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser("warp", help="carry a picture from F's attractor onto G's (fractal tops, 3.3.5)",
                              description=__doc__.split("\n\n")[1].replace("\n", " "))
    p.add_argument("picture", help="a PNG picture laid on F's frame")
    p.add_argument("--from", dest="source", required=True, help="system F (" + common.SYSTEM_HELP + ")")
    p.add_argument("--to", dest="target", required=True, help="system G, with as many maps as F")
    p.add_argument("-o", "--output", required=True, help="OUT.png, or a folder with --frames")
    p.add_argument("--size", default="512", help="N or WxH pixels of the output (default 512)")
    p.add_argument("--frames", type=common.int_option(0, 100000), default=0, help="K frames of F moving to G into the folder -o")
    p.add_argument("--iterations", type=common.int_option(0, 10**12), default=ifsforge.TopsOptions().iterations,
                   help="chaos-game points (0: rounds of 16 per pixel until G's attractor is found)")
    p.add_argument("--seed", type=common.SEED, default=ifsforge.TopsOptions().seed)
    p.set_defaults(run=run)


def run(args):
    source = common.load_system(args.source)
    target = common.load_system(args.target)
    width, height = common.parse_size(args.size)
    picture = ifsforge.read_png(args.picture)
    if args.frames:
        if args.frames < 2:
            raise ifsforge.InputError(f"--frames expects at least 2, got {args.frames}")
        with common.staged_folder(args.output) as staging:  # one frame in memory at a time
            for k in range(args.frames):
                frame = ifsforge.tops_warp(source, picture, ifsforge.morph(source, target, k / (args.frames - 1)),
                                           width, height, seed=args.seed, iterations=args.iterations)
                ifsforge.write_png(os.path.join(staging, f"frame_{k:04d}.png"), frame)
        print(f"{args.output}: {args.frames} frames")
        return 0
    common.ensure_output_folder(args.output)
    warped = ifsforge.tops_warp(source, picture, target, width, height, seed=args.seed, iterations=args.iterations)
    ifsforge.write_png(args.output, warped)
    print(f"{args.output}: {width}x{height}, {int((warped[..., 3] > 0).sum())} pixels of G's attractor colored")
    return 0
