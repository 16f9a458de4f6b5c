"""ifsforge breed: random polar systems (seed 3.3.3, Eq. 32), the seed's phenotypes (section 7), on a contact sheet.

Each phenotype is drawn from its own random stream (seed, index) and redrawn from it until its
attractor is neither a point nor a blob (ifsforge.BreedOptions), so a seed always breeds the same
systems. Each is rendered with random iteration (chaos) into one cell of the sheet and written as
JSON: DIR/phenotype_NN.json, where DIR is the sheet's path without '.png' unless --json-dir is given.
The sheet and the JSON files are written all or none.
"""
import colorsys
import os

import ifsforge
from ifsforge import cli_common as common

SIZE = 256     # pixels per phenotype on the sheet
COLUMNS = 4


def register(subparsers):
    o = ifsforge.BreedOptions()  # every breeding default is the core's, written once in C++
    p = subparsers.add_parser("breed", help="random locally contractive polar systems on a contact sheet",
                              description=__doc__.split("\n\n")[1].replace("\n", " "))
    p.add_argument("-o", "--output", required=True, help="the contact sheet (.png)")
    p.add_argument("--count", type=common.int_option(1, 4096), default=o.count, help="phenotypes")
    p.add_argument("--seed", type=common.SEED, default=o.seed)
    p.add_argument("--maps", type=common.int_option(0, 16), default=o.maps, help="maps per phenotype (2..16); 0: 2 to 4, drawn")
    p.add_argument("--size", type=common.int_option(16, 4096), default=SIZE, help="pixels per phenotype")
    p.add_argument("--columns", type=common.int_option(1, 64), default=COLUMNS)
    p.add_argument("--json-dir", help="folder of the phenotypes' JSON (default: the sheet's path without .png)")
    p.add_argument("--threads", type=common.THREADS, default=0, help="0: every core (the output does not depend on it)")
    p.set_defaults(run=run)


def tinted(raster, k):
    """The density picture in a hue of its own (golden-ratio steps round the color wheel):
    faint regions take the hue, dense ones go towards white."""
    import numpy as np

    grey = np.asarray(raster.to_image(mode="density"), np.float32)
    if grey.ndim == 3:
        grey = grey[:, :, :3].mean(axis=2)
    hue = colorsys.hsv_to_rgb((0.12 + 0.618034 * k) % 1.0, 0.75, 1.0)
    tint = np.asarray(hue, np.float32)[None, None, :]
    g = np.sqrt(grey[:, :, None])  # lifts the faint swirls that most of a polar attractor is
    return np.clip(g * tint + g ** 4 * (1.0 - tint), 0.0, 1.0)


def run(args):
    from ifsforge.contact_sheet import contact_sheet

    if not args.output.lower().endswith(".png"):
        raise ifsforge.InputError(f"--output: the contact sheet is a PNG, got '{args.output}'")
    common.ensure_output_folder(args.output)
    folder = args.json_dir or os.path.splitext(args.output)[0]
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise ifsforge.FileError(f"cannot write phenotypes into '{folder}': it is not a folder")
    # Each phenotype's picture is kept for the sheet (float RGB, with its density raster while
    # it is made), and the sheet holds them all again.
    ifsforge.check_memory(args.count * args.size * args.size * 40.0, f"{args.count} phenotypes of {args.size}^2 pixels")
    systems = ifsforge.breed(count=args.count, seed=args.seed, maps=args.maps)
    images, labels = [], []
    for k, system in enumerate(systems):
        raster = ifsforge.render(system, "chaos", args.size, threads=args.threads)
        images.append(tinted(raster, k))
        s = max(m.contraction() for m in system.polar_maps)
        labels.append(f"{k:02d}: {len(system)} maps, s {s:.2f}")
    sheet = contact_sheet(images, labels, columns=min(args.columns, len(images)), cell=args.size)
    os.makedirs(folder, exist_ok=True)
    paths = [os.path.join(folder, f"phenotype_{k:02d}.json") for k in range(len(systems))]
    with common.all_or_none([args.output] + paths) as staged:
        ifsforge.write_png(staged[args.output], sheet)
        for path, system in zip(paths, systems):
            ifsforge.write_json(staged[path], system)
    print(f"{args.output}: {len(systems)} phenotypes (seed {args.seed}); their systems in {folder}/")
    return 0
