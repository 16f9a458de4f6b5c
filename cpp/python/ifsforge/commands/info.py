"""ifsforge info: the maps and what can be derived from them."""

import os

import ifsforge
from ifsforge import cli_common as common


def register(subparsers):
    p = subparsers.add_parser("info", help="maps, contraction factors, classification, bounds, dimension, "
                                           "transitions, super IFS members, condensation set")
    p.add_argument("system", help=common.SYSTEM_HELP + ", or a .pifs compressed image")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.add_argument("--dimension-size", type=common.int_option(16, 16384), default=1024,
                   help="image size for the box-counting estimate (2D systems)")
    p.set_defaults(run=run)


def describe(system, dimension_size=1024):
    """Everything `info` prints, as a dict (plain values from the core: a small info never
    imports numpy)."""
    out = system.summary()
    out.update(describe_extensions(system))
    # chaos refuses condensation sets rather than ignore them (they are no map to iterate).
    if "bounds" in out and system.spatial_dims == 2 and system.condensation is None:
        # Random iteration with Eq. 45's count: fast for every system, overlapping or not.
        raster = ifsforge.render(system, "chaos", dimension_size, binary=True)
        try:
            counting = ifsforge.box_counting(raster)
            out["box_counting_dimension"] = counting.dimension
            out["box_sizes"] = list(counting.box_sizes)
        except ifsforge.InputError as error:  # too few pixels for a slope worth printing
            out["box_counting_dimension"] = None
            out["box_counting_refused"] = str(error)
    return out


def describe_extensions(system):
    """The model's extensions that are set on `system` (at most one of them is)."""
    out = {}
    if system.super_ifs is not None:
        out["super_ifs"] = describe_super_ifs(system)
    if system.condensation is not None:
        out["condensation"] = describe_condensation(system)
    return out


def describe_super_ifs(system):
    """3.3.5, Eq. 38: member n owns consecutive maps and is chosen with probability P_n."""
    parts = system.super_ifs
    members, first = [], 0
    for n, (name, size, p) in enumerate(zip(parts["names"], parts["sizes"], parts["probabilities"])):
        members.append({
            "name": name, "probability": float(p), "map_count": size,
            "map_indices": list(range(first, first + size)),
            "map_probabilities": system.member(n).probabilities.tolist(),
        })
        first += size
    return {"variability": parts["variability"], "members": members}


def describe_condensation(system):
    """Definitions 8-9: the set C of w_0, its shapes, p_0 and its values of the extra channels."""
    c = system.condensation
    extra = system.channel_names[system.spatial_dims:]
    return {
        "probability": c.probability,
        "polygons": [len(path) for path in c.polygons],
        "polylines": [len(path) for path in c.polylines],
        "bounds": list(c.bounds()),
        # The sampled bounds below are those of the maps' attractor; C and its images add to it.
        "attractor_box": list(system.condensation_box),
        "channels": dict(zip(extra, c.channels)),
    }


def print_transitions(rows):
    print("transitions (row i: probability that map j follows map i):")
    print("          " + "".join(f"{f'map {j}':>8}" for j in range(1, len(rows) + 1)))
    for i, row in enumerate(rows, 1):
        print(f"  {f'map {i}':<8}" + "".join(f"{v:8.4f}" for v in row))


def print_super_ifs(parts):
    members = parts["members"]
    print(f"super IFS: {len(members)} member systems, variability V={parts['variability']}")
    for n, m in enumerate(members, 1):
        first, last = m["map_indices"][0] + 1, m["map_indices"][-1] + 1
        print(f"  member {n} '{m['name']}': P={m['probability']:.4f}  {m['map_count']} maps "
              f"(maps {first}-{last}, p=" + " ".join(f"{p:.4f}" for p in m["map_probabilities"]) + ")")


def print_condensation(c):
    def counted(sizes, what):
        return f"{len(sizes)} {what}{'' if len(sizes) == 1 else 's'}" + \
            (" (" + ", ".join(f"{k} points" for k in sizes) + ")" if sizes else "")
    xmin, ymin, xmax, ymax = c["bounds"]
    print(f"condensation set: {counted(c['polygons'], 'polygon')}, {counted(c['polylines'], 'polyline')}, "
          f"p0={c['probability']:.4f}")
    print(f"  box: x [{xmin:.6g}, {xmax:.6g}]  y [{ymin:.6g}, {ymax:.6g}]")
    xmin, ymin, xmax, ymax = c["attractor_box"]
    print(f"  attractor with C and its images within x [{xmin:.6g}, {xmax:.6g}]  y [{ymin:.6g}, {ymax:.6g}]")
    if c["channels"]:
        print("  channels: " + "  ".join(f"{name}={v:.6g}" for name, v in c["channels"].items()))


def print_polar_map(i, m):
    """3.3.3: s is the local contraction ratio about the centre (Eq. 30), not a spectral norm."""
    p = m["polar"]
    print(f"  map {i}: polar  p={m['probability']:.4f}  s={m['contraction_factor']:.4f} (local, about "
          f"P=({p['center'][0]:.4g}, {p['center'][1]:.4g}), Eq. 30)  k={p['k']:.4g}  sup F={p['f_bound']:.4g}")
    print("      F: [" + " ".join(f"{v:.4f}" for v in p["F"]) + "]  G: [" + " ".join(f"{v:.4f}" for v in p["G"]) +
          f"]  winding {p['winding']}")


def run(args):
    if args.system.lower().endswith(".pifs"):  # a fractal-compressed image (ifsforge compress)
        return pifs_info(args)
    system = common.load_system(args.system)
    info = describe(system, args.dimension_size)
    if args.json:
        print(common.to_json(info))
        return 0
    print(f"{info['name']}  ({info['layout']}, {len(info['maps'])} maps)")
    for i, m in enumerate(info["maps"], 1):
        fp = "none" if m["fixed_point"] is None else "(" + ", ".join(f"{v:.4g}" for v in m["fixed_point"]) + ")"
        if "polar" in m:
            print_polar_map(i, m)
            continue
        print(f"  map {i}: p={m['probability']:.4f}  s={m['contraction_factor']:.4f}  "
              f"det={m['determinant']:.4g}  fixed point {fp}")
        for row, b in zip(m["matrix"], m["offset"]):
            print("      [" + " ".join(f"{v:9.4f}" for v in row) + f" ] + {b:.4f}")
    if "transitions" in info:
        print_transitions(info["transitions"])
    if "super_ifs" in info:
        print_super_ifs(info["super_ifs"])
    if "condensation" in info:
        print_condensation(info["condensation"])
    lyapunov = "" if info["lyapunov_exponent"] is None else f", Lyapunov {info['lyapunov_exponent']:.4f}"
    print(f"classification: {info['classification']}  (max s = {info['contraction_ratio']:.4f}, "
          f"sum p log s = {info['average_log_contraction']:.4f}{lyapunov})")
    for name, (lo, hi) in info.get("bounds", {}).items():
        print(f"  {name}: [{lo:.6g}, {hi:.6g}]")
    if info.get("box_counting_dimension") is not None:
        print(f"box-counting dimension: {info['box_counting_dimension']:.4f} (boxes of "
              f"{', '.join(map(str, info['box_sizes']))} pixels on a {args.dimension_size}^2 image)")
    elif "box_counting_refused" in info:
        print(f"box-counting dimension: not estimated at {args.dimension_size}^2: {info['box_counting_refused']}")
    return 0


def pifs_info(args):
    from ifsforge.commands import compress
    info = compress.describe_code(ifsforge.read_pifs(args.system), os.path.getsize(args.system))
    if args.json:
        print(common.to_json(info))
    else:
        compress.print_description(info)
    return 0
