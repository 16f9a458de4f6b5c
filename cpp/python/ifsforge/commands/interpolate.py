"""ifsforge interpolate: the fractal interpolation function of data points (Eq. 90-94), as an
IFS (ifsforge/1 JSON, for render and info) or as exact samples (CSV)."""
import os

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser(
        "interpolate", help="fractal interpolation of data points: the IFS (JSON) or samples (CSV)",
        description="Build the maps of Eq. 94 through the points (x_i, F_i) with vertical scaling "
        "factors a22 (|a22| < 1) and write the IFS or the function's exact values.")
    p.add_argument("--x", type=common.NUMBER, nargs="+", required=True, help="increasing x_0 < x_1 < ... < x_N (N >= 2)")
    p.add_argument("--values", type=common.NUMBER, nargs="+", required=True, help="F_0 ... F_N")
    p.add_argument("--a22", type=common.float_option(-1, 1), nargs="+", required=True, help="one factor per map (N), or one for all")
    p.add_argument("-o", "--output", action="append", required=True,
                   help=".json (the IFS, layout xy) or .csv (x, f(x) at --samples points)")
    p.add_argument("--samples", type=common.int_option(2, 10**8), default=1025, help="CSV rows (equally spaced from x_0 to x_N)")
    p.add_argument("--name", default="fractal interpolation")
    p.set_defaults(run=run)


def write_text(path, text):
    ifsforge.write_bytes(path, text)


def run(args):
    for path in args.output:
        if os.path.splitext(path)[1].lower() not in (".json", ".csv"):
            raise ifsforge.InputError(f"cannot write '{path}': interpolate writes .json or .csv")
        common.ensure_output_folder(path)
    f = ifsforge.FractalInterpolation(args.x, args.values, args.a22)
    print(f"{f.maps()} maps, box-counting dimension of the graph {f.dimension():.4f}")
    for path in args.output:
        if path.lower().endswith(".json"):
            ifsforge.write_json(path, f.to_ifs(args.name))
            print(f"{path}: the IFS (render it with `ifsforge render {path}`)")
        else:
            # The CSV is built in memory before its atomic write: about 100 bytes a row at most.
            ifsforge.check_memory(args.samples * 100.0, f"{args.samples:,} CSV rows")
            values = f.sample(args.samples)
            x0, x1 = args.x[0], args.x[-1]
            rows = ["x,f"]
            for t, v in enumerate(values):
                x = x1 if t == len(values) - 1 else x0 + (x1 - x0) * t / (len(values) - 1)
                rows.append(f"{x!r},{v!r}")
            write_text(path, "\n".join(rows) + "\n")
            print(f"{path}: {len(values)} exact samples")
