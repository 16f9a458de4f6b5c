"""ifsforge compress: fractal (partitioned IFS) compression of a PNG image (seed 3.3.2)."""
import sys

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser(
        "compress", help="fractal-compress a PNG image to a .pifs code (decodes at any resolution)",
        description="Partitioned IFS coding (seed 3.3.2): quadtree range cells, domain cells twice their "
        "size found by nearest-neighbour search, contrast and brightness by least squares (Eq. 29), "
        "range-coded. Color is coded as YCbCr with half-size chroma; alpha as its own plane.")
    o = ifsforge.PifsEncodeOptions()
    p.add_argument("image", help="a PNG image (gray, gray+alpha, RGB or RGBA; 16-bit is reduced to 8)")
    p.add_argument("-o", "--output", required=True, help="the .pifs file to write")
    rate = p.add_mutually_exclusive_group()
    rate.add_argument("--ratio", type=common.float_option(1, 1e6), help="compression ratio R: the file is at most raw bytes / R")
    rate.add_argument("--bytes", type=common.count_option(2**62), help="the file is at most N bytes")
    rate.add_argument("--quality", type=common.float_option(0, 255),
                      help=f"collage RMS error threshold in 8-bit levels (smaller is better; default {o.quality:g})")
    p.add_argument("--min-block", type=common.int_option(0, 4096), default=o.min_block,
                   help="smallest range cell, pixels (power of two, at least 2; 0: 8 with the residual layer, "
                   "else 2 at ratios up to 16:1, else 4)")
    p.add_argument("--max-block", type=common.count_option(4096), default=o.max_block, help="largest range cell, pixels (power of two)")
    p.add_argument("--no-ycbcr", action="store_true", help="code R, G, B as they are (no YCbCr)")
    p.add_argument("--chroma", choices=ifsforge.choices["chroma"], default=o.chroma,
                   help="YCbCr chroma: half (4:2:0), full (4:4:4) or auto (full where half-size chroma would cap "
                        "the quality of a --ratio or --bytes target)")
    p.add_argument("--no-residual", action="store_true",
                   help="with --ratio or --bytes: the fractal code alone (no DCT residual layer for what it misses)")
    p.add_argument("--search", choices=ifsforge.choices["search"], default=o.search,
                   help="domain search: tree (fast), or exhaustive (every domain and isometry: the slow reference)")
    p.add_argument("--threads", type=common.THREADS, default=o.threads, help="threads (0: all cores); the file is the same")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(run=run)


def png_bit_depth(path):
    """The bit depth in a PNG's IHDR (None when the file is not a PNG)."""
    with open(path, "rb") as f:
        head = f.read(25)
    if len(head) < 25 or head[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    return head[24]


def describe_code(code, file_bytes=None):
    """What `info` and `compress` print about a code, as a dict. `file_bytes`: the size of the file
    it was read from (an older format version's differs from the current one's)."""
    cost = code.cost()
    if file_bytes is not None:
        cost["bytes"] = file_bytes
    raw = code.width * code.height * code.channels
    return {
        "format": "pifs", "width": code.width, "height": code.height, "channels": code.channels,
        "color": code.color, "min_block": code.min_block, "max_block": code.max_block,
        "s_bits": code.s_bits, "dc_step": code.dc_step, "planes": [list(s) for s in code.plane_sizes],
        "leaves": list(code.leaf_counts), "bytes": cost["bytes"], "ratio": raw / cost["bytes"],
        "bits_per_pixel": 8.0 * cost["bytes"] / (code.width * code.height),
        "cost_bits": {k[:-5]: round(v, 1) for k, v in cost.items() if k.endswith("_bits")},
        "flat_leaves": cost["flat_leaves"],
    }


def print_description(info):
    print(f"PIFS {info['width']}x{info['height']}, {info['channels']} channel(s), color {info['color']}, "
          f"range cells {info['min_block']}..{info['max_block']} px, s {info['s_bits']} bits")
    print(f"  {info['bytes']} bytes, {info['ratio']:.1f}:1, {info['bits_per_pixel']:.3f} bpp; "
          f"{sum(info['leaves'])} range cells ({info['flat_leaves']} flat) in planes "
          + ", ".join(f"{w}x{h}: {n}" for (w, h), n in zip(info["planes"], info["leaves"])))
    total = sum(info["cost_bits"].values())
    print("  cost: " + ", ".join(f"{k} {v / 8:.0f} B ({100 * v / total:.0f}%)" for k, v in info["cost_bits"].items()))


def run(args):
    common.ensure_output_folder(args.output)
    depth = png_bit_depth(args.image)
    if depth is None:
        raise ifsforge.InputError(f"'{args.image}' is not a PNG image")
    image = ifsforge.read_png(args.image)
    if depth == 16:
        print(f"ifsforge compress: note: '{args.image}' is 16-bit; reduced to 8 bits per sample", file=sys.stderr)
    code = ifsforge.pifs_encode(image, ratio=args.ratio, bytes=args.bytes, quality=args.quality,
                                min_block=args.min_block, max_block=args.max_block,
                                ycbcr=not args.no_ycbcr, chroma=args.chroma, residual=not args.no_residual,
                                search=args.search, threads=args.threads)
    ifsforge.write_pifs(args.output, code)
    info = describe_code(code)
    if args.json:
        print(common.to_json(info))
    else:
        print_description(info)
    return 0
