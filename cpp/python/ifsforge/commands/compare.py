"""ifsforge compare: one system rendered by every chapter-5 algorithm, side by side.

The modern version of the seed's 5.13.1: for each algorithm the wall time, its own operation
count (Raster.points, defined per algorithm) beside the seed's estimate for a 1000 x 1000
image of a 5-map IFS, the pixels covered and the agreement (intersection over union of the
binary images) with the point recursive reference. Writes DIR/contact_sheet.png (labelled
thumbnails), DIR/<algorithm>.png, DIR/comparison.md and DIR/comparison.json.
"""
import os
import time

import numpy as np

import ifsforge
from ifsforge import cli_common as common
from ifsforge.contact_sheet import contact_sheet
from ifsforge.progress import ProgressBar

# Pixel-grid algorithms (default supersample 2): the comparison also reports them at supersample 1.
PIXEL_GRID = ("dia", "dia-s", "mpa", "cma", "ibr", "self-congruent", "photocopy")


def register(subparsers):
    p = subparsers.add_parser("compare", help="render one system with every algorithm and compare them",
                              description=__doc__.split("\n\n")[1].replace("\n", " "))
    common.add_system_argument(p)
    p.add_argument("-o", "--output", required=True, help="folder for the contact sheet, images and table")
    p.add_argument("--size", default="512", help="N or WxH pixels (default 512)")
    p.add_argument("--algorithms", help="comma-separated subset (default: all but color-stealing)")
    p.add_argument("--threads", type=common.THREADS, default=0, help="0: every core")
    p.add_argument("--seed", type=common.SEED, default=0)
    p.add_argument("--param", action="append", default=[], metavar="[ALGORITHM.]KEY=VALUE",
                   help="a setting for one algorithm (ALGORITHM.KEY) or for every algorithm that takes KEY")
    p.set_defaults(run=run)


def reference_algorithm(system):
    """The point recursive reference: PRR, or for a recurrent IFS its recursive algorithm
    (5.12.2). PRR does not draw condensation sets: then deterministic iteration on a grid
    twice as fine stands in."""
    if system.recurrent:
        return "probabilistic-domain", {}
    if system.condensation is not None:
        return "dia", {"supersample": 2}
    return "prr", {}


def settings_for(algorithm, overrides):
    """The --param values that apply to `algorithm`."""
    known = {key for key, _, _ in ifsforge.renderer_parameters(algorithm)}
    out = {}
    for key, value in overrides.items():
        target, dot, name = key.rpartition(".")
        if dot and target == algorithm:
            out[name] = value
        elif not dot and key in known:
            out[key] = value
    return out


def iou(a, b):
    union = np.logical_or(a, b).sum()
    return float(np.logical_and(a, b).sum() / union) if union else 1.0


def compare(system, size=(512, 512), algorithms=None, threads=0, seed=0, overrides=None, progress=True):
    """Renders `system` with every algorithm; returns (rows, images, reference name). Each row
    is a dict: algorithm, section, ms, operations, seed_operations, covered, iou, note."""
    overrides = overrides or {}
    names = [n for n, _ in ifsforge.renderers() if n not in ("color-stealing", "tops")]  # both need a picture
    if algorithms:
        unknown = [a for a in algorithms if a not in names]
        if unknown:
            raise ifsforge.InputError(f"unknown algorithm(s) {', '.join(unknown)}; choose from {', '.join(names)}")
        names = [n for n in names if n in algorithms]
    width, height = size
    defaults = system.render_defaults
    window, view = defaults.get("window"), defaults.get("view")
    # One frame for everyone: the reference's window when the system names none.
    ref_name, ref_params = reference_algorithm(system)
    common_args = dict(window=window, view=view, threads=threads, seed=seed)
    reference = ifsforge.render(system, ref_name, width, height, binary=True,
                                parameters={**ref_params, **settings_for(ref_name, overrides)}, **common_args)
    rows, images = [], {}
    for name in names:
        params = settings_for(name, overrides)
        section, seed_operations = ifsforge.seed_reference(name)  # kept on the C++ registry
        row = {"algorithm": name, "section": section, "seed_operations": seed_operations}
        bar = ProgressBar(f"compare {name}", enabled=None if progress else False)
        try:
            start = time.perf_counter()
            raster = ifsforge.render(system, name, width, height, binary=True, parameters=params,
                                     progress=bar, **common_args)
            row["ms"] = (time.perf_counter() - start) * 1000.0
        except ifsforge.InputError as error:
            row.update(ms=None, operations=None, covered=None, iou=None, note=str(error))
            rows.append(row)
            continue
        row.update(operations=raster.points, covered=raster.covered(), iou=iou(raster.mask, reference.mask),
                   note=", ".join(f"{k}={v}" for k, v in params.items()))
        if name in PIXEL_GRID and "supersample" not in params:
            coarse = ifsforge.render(system, name, width, height, binary=True,
                                     parameters={**params, "supersample": 1}, **common_args)
            row["iou_supersample_1"] = iou(coarse.mask, reference.mask)
        images[name] = raster.to_image()
        rows.append(row)
    return rows, images, f"{ref_name}" + "".join(f" {k}={v}" for k, v in ref_params.items())


def number(value):
    if value is None:
        return "n/a"
    for limit, suffix in ((1e9, " G"), (1e6, " M"), (1e3, " k")):
        if value >= limit:
            return f"{value / limit:.3g}{suffix}"
    return f"{value:.0f}"


def markdown(system, rows, reference, size):
    lines = [f"# {system.name}: every algorithm at {size[0]}x{size[1]}", "",
             f"Reference for the agreement (IoU of the binary images): `{reference}`. Operations are "
             "each algorithm's own count (`Raster.points`); the seed's estimates (5.13.1) are for a "
             "1000 x 1000 image of a 5-map IFS.", "",
             "| algorithm | seed | time (ms) | operations | seed estimate | pixels | IoU | IoU (supersample 1) | note |",
             "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |"]
    for r in rows:
        ms = "n/a" if r["ms"] is None else f"{r['ms']:.1f}"
        agreement = "n/a" if r["iou"] is None else f"{r['iou']:.3f}"
        coarse = f"{r['iou_supersample_1']:.3f}" if "iou_supersample_1" in r else ""
        covered = "n/a" if r["covered"] is None else str(r["covered"])
        lines.append(f"| {r['algorithm']} | {r['section']} | {ms} | {number(r['operations'])} | "
                     f"{number(r['seed_operations'])} | {covered} | {agreement} | {coarse} | {r['note']} |")
    return "\n".join(lines) + "\n"


def run(args):
    system = common.load_system(args.system)
    size = common.parse_size(args.size)
    algorithms = [a.strip() for a in args.algorithms.split(",")] if args.algorithms else None
    overrides = common.parse_parameters(args.param)
    with common.staged_folder(args.output) as staging:
        rows, images, reference = compare(system, size, algorithms, args.threads, args.seed, overrides)
        for name, image in images.items():
            ifsforge.write_png(os.path.join(staging, f"{name}.png"), image)
        done = [r for r in rows if r["algorithm"] in images]
        sheet = contact_sheet([images[r["algorithm"]] for r in done],
                              [f"{r['algorithm']}\n{r['ms']:.0f} ms  iou {r['iou']:.3f}" for r in done])
        ifsforge.write_png(os.path.join(staging, "contact_sheet.png"), sheet)
        text = markdown(system, rows, reference, size)
        for name, content in (("comparison.md", text),
                              ("comparison.json", common.to_json({"system": system.name, "size": list(size),
                                                                    "reference": reference, "rows": rows}))):
            ifsforge.write_bytes(os.path.join(staging, name), content)
    print(text, end="")
    print(f"{args.output}: contact_sheet.png, comparison.md, comparison.json and {len(images)} images")
    return 0
