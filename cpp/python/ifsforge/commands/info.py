"""ifsforge info: the maps and what can be derived from them."""
import json

import numpy as np

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser("info", help="maps, contraction factors, classification, bounds, dimension")
    common.add_system_argument(p)
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--dimension-size", type=int, default=1024,
                   help="image size for the box-counting estimate (2D systems)")
    p.set_defaults(run=run)


def describe(system, dimension_size=1024):
    """Everything `info` prints, as a dict."""
    factors = system.contraction_factors()
    classification = system.classify()
    out = {
        "name": system.name,
        "layout": system.layout,
        "channels": system.channel_names,
        "maps": [],
        "classification": classification,
        "contraction_ratio": float(factors.max()),
        "average_log_contraction": float(system.average_log_contraction()),
        "lyapunov_exponent": float(system.lyapunov_exponent()),
    }
    fixed = system.fixed_points()
    for i, m in enumerate(system.maps):
        out["maps"].append({
            "matrix": m.matrix.tolist(), "offset": m.offset.tolist(),
            "probability": float(system.probabilities[i]), "contraction_factor": float(factors[i]),
            "determinant": float(m.determinant(system.spatial_dims)),
            "fixed_point": None if np.isnan(fixed[i]).any() else fixed[i].tolist(),
        })
    if classification != "divergent":
        lo, hi = system.attractor_bounds()
        out["bounds"] = {name: [float(a), float(b)] for name, a, b in zip(system.channel_names, lo, hi)}
        if system.spatial_dims == 2:
            # Random iteration with Eq. 45's count: fast for every system, overlapping or not.
            raster = ifsforge.render(system, "chaos", dimension_size, binary=True)
            out["box_counting_dimension"] = ifsforge.box_counting(raster).dimension
    return out


def run(args):
    system = common.load_system(args.system)
    info = describe(system, args.dimension_size)
    if args.json:
        print(json.dumps(info, indent=2))
        return 0
    print(f"{info['name']}  ({info['layout']}, {len(info['maps'])} maps)")
    for i, m in enumerate(info["maps"], 1):
        fp = "none" if m["fixed_point"] is None else "(" + ", ".join(f"{v:.4g}" for v in m["fixed_point"]) + ")"
        print(f"  map {i}: p={m['probability']:.4f}  s={m['contraction_factor']:.4f}  "
              f"det={m['determinant']:.4g}  fixed point {fp}")
        for row, b in zip(m["matrix"], m["offset"]):
            print("      [" + " ".join(f"{v:9.4f}" for v in row) + f" ] + {b:.4f}")
    print(f"classification: {info['classification']}  (max s = {info['contraction_ratio']:.4f}, "
          f"sum p log s = {info['average_log_contraction']:.4f}, Lyapunov {info['lyapunov_exponent']:.4f})")
    for name, (lo, hi) in info.get("bounds", {}).items():
        print(f"  {name}: [{lo:.6g}, {hi:.6g}]")
    if "box_counting_dimension" in info:
        print(f"box-counting dimension: {info['box_counting_dimension']:.4f}")
    return 0
