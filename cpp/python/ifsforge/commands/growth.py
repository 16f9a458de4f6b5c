"""ifsforge growth: self-congruent growth (seed 5.11) as a sequence of frames."""
import os

import ifsforge
from ifsforge import cli_common as common
from ifsforge.progress import ProgressBar


def register(subparsers):
    p = subparsers.add_parser("growth", help="grow a system cycle by cycle (5.11): one PNG per frame",
                              description="Self-congruent growth: the initiator (the system's condensation "
                              "set, else the maps' fixed points) transformed by the maps, a growth cycle per "
                              "frame, until nothing new grows. Writes DIR/frame_0000.png ...")
    common.add_system_argument(p)
    p.add_argument("-o", "--output", required=True, help="folder for the frames")
    p.add_argument("--size", default=None, help="N or WxH pixels (default: the system's, else 512)")
    p.add_argument("--cycle", type=common.count_option(4096), default=1, help="generations of growth per frame")
    p.add_argument("--supersample", type=common.count_option(64), default=1, help="pixel grid k times finer than the image")
    p.add_argument("--mode", default="auto", choices=["auto", "binary", "density", "color"],
                   help="density shows each pixel's age in cycles; color the channel values")
    p.add_argument("--bits", type=int, default=8, choices=[8, 16])
    p.add_argument("--threads", type=common.THREADS, default=0)
    p.set_defaults(run=run)


def run(args):
    system = common.load_system(args.system)
    defaults = system.render_defaults
    width, height = common.parse_size(args.size) if args.size else defaults.get("size", (512, 512))
    with common.staged_folder(args.output) as staging:
        frames = ifsforge.growth_frames(system, width, height, window=defaults.get("window"), threads=args.threads,
                                        parameters={"cycle": args.cycle, "supersample": args.supersample},
                                        progress=ProgressBar(f"growth {system.name}"))
        for k, frame in enumerate(frames):
            ifsforge.write_png(os.path.join(staging, f"frame_{k:04d}.png"), frame.to_image(args.mode), args.bits)
    print(f"{args.output}: {len(frames)} frames of {width}x{height}, "
          f"{frames[-1].covered()} pixels grown in the last")
    return 0
