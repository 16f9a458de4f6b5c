"""ifsforge palette: a fractal palette (seed 6.1.3.3) as a PNG strip or texture, a POV-Ray
color_map, or applied to a gray image."""
import os

import ifsforge
from ifsforge import cli_common as common

OUTPUTS = (".png", ".inc")


def register(subparsers):
    p = subparsers.add_parser(
        "palette", help="a fractal palette: PNG strip/texture, POV-Ray color_map, or applied to an image",
        description="Interpolate color stops component by component with fractal interpolation "
        "(Eq. 94); the a22 factors are the roughness. From a recipe (ifsforge-palette/1 JSON) or "
        "from the options.")
    p.add_argument("recipe", nargs="?", help="a palette recipe (JSON); without it give --stops")
    p.add_argument("-o", "--output", action="append", default=[],
                   help="file to write, by extension: .png (the palette, entries wide, --rows high), "
                   ".inc (a POV-Ray #declare of a color_map); repeat for several")
    p.add_argument("--space", choices=ifsforge.choices["space"], help="color space of the stops (default rgb)")
    p.add_argument("--stops", nargs="+", metavar="A,B,C",
                   help="color stops, three comma-separated components each (hls/hsi: hue in degrees)")
    p.add_argument("--positions", type=common.float_option(0, 1), nargs="+", help="stop positions from 0 to 1 (default even)")
    p.add_argument("--roughness", type=common.float_option(-1, 1), nargs=3, metavar=("R1", "R2", "R3"),
                   help="|a22| of each component (overrides the recipe's)")
    p.add_argument("--signs", choices=ifsforge.choices["signs"], default="random")
    p.add_argument("--seed", type=common.SEED, default=0, help="seed of the random signs")
    p.add_argument("--entries", type=common.int_option(2, 65536), help=f"palette entries (default the recipe's, or {ifsforge.PaletteRecipe().entries})")
    p.add_argument("--rows", type=common.count_option(4096), default=1, help="PNG rows: 1 for a strip, more for an N x M texture")
    p.add_argument("--bits", type=int, choices=[8, 16], default=8)
    p.add_argument("--apply", nargs=2, metavar=("GRAY.png", "OUT.png"),
                   help="color a gray image (a height field) through the palette")
    p.add_argument("--name", help="name of the POV-Ray color_map, declared as IFS_Palette_<name> "
                   "(default: the recipe's name)")
    p.set_defaults(run=run)


def parse_stop(text):
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 3:
        raise ifsforge.InputError(f"--stops: '{text}' is not three comma-separated numbers")
    return values


def write_text(path, text):
    ifsforge.write_bytes(path, text)


def run(args):
    if not args.output and not args.apply:
        raise ifsforge.InputError("nothing to write: give -o FILE and/or --apply GRAY.png OUT.png")
    for path in args.output:
        if os.path.splitext(path)[1].lower() not in OUTPUTS:
            raise ifsforge.InputError(f"cannot write '{path}': palette outputs end in .png or .inc")
        common.ensure_output_folder(path)
    if args.apply:
        common.ensure_output_folder(args.apply[1])

    if args.recipe:
        if args.stops or args.space or args.positions:
            raise ifsforge.InputError("--stops, --space and --positions describe a palette without a recipe")
        recipe = ifsforge.read_palette_recipe(args.recipe)
        spec, name, entries, description = recipe.spec, recipe.name, recipe.entries, recipe.description
    else:
        if not args.stops:
            raise ifsforge.InputError("give a palette recipe or --stops")
        spec = ifsforge.PaletteSpec(args.space or "rgb", [parse_stop(s) for s in args.stops], args.positions or [])
        name, entries, description = "palette", ifsforge.PaletteRecipe().entries, ""
    if args.roughness:
        maps = len(spec.stops) - 1
        spec.a22 = [ifsforge.vertical_scaling(maps, r, args.signs, args.seed, k) for k, r in enumerate(args.roughness)]
    entries = args.entries or entries
    palette = ifsforge.make_palette(spec, entries)

    for path in args.output:
        if path.lower().endswith(".png"):
            ifsforge.write_png(path, palette.to_image(args.rows), args.bits)
            print(f"{path}: {spec.space} fractal palette, {entries}x{args.rows}, {args.bits}-bit")
        else:
            about = f"{spec.space}, {len(spec.stops)} stops" + (f"\n{description}" if description else "")
            text = palette.pov_include(args.name or name, about, entries)
            write_text(path, text)
            identifier = ifsforge.pov_identifier("Palette", args.name or name)
            print(f"{path}: POV-Ray color_map {identifier} ({min(entries, 256)} entries)")
    if args.apply:
        source, target = args.apply
        colored = ifsforge.apply_palette(ifsforge.read_png(source), palette)
        ifsforge.write_png(target, colored, args.bits)
        print(f"{target}: {source} colored by the palette")
