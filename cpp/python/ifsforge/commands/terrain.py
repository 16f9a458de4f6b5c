"""ifsforge terrain: a 2.5D IFS terrain (seed 6.1.3.4) as a height PNG, a mesh or a POV-Ray scene."""
import contextlib
import math
import os

import ifsforge
from ifsforge import cli_common as common
from ifsforge.progress import ProgressBar

MESHES = (".glb", ".obj", ".ply")
OUTPUTS = (".png", ".pov") + MESHES


def register(subparsers):
    # The defaults are the core's (controls, POV-Ray scene and render): written once, in C++.
    t, pov, render = ifsforge.TerrainControlsOptions(), ifsforge.TerrainPovOptions(), ifsforge.PovRenderOptions()
    d = ifsforge.terrain_defaults
    p = subparsers.add_parser(
        "terrain", help="a fractal-interpolation terrain: 16-bit height PNG, mesh, POV-Ray scene",
        description="Interpolate control heights into a terrain: leading vectors first, then every "
        "vertical (radial) vector, each a fractal interpolation (Eq. 94). From a recipe "
        "(ifsforge-terrain/1 JSON) or from the options (random or map-sampled controls).")
    p.add_argument("recipe", nargs="?", help="a terrain recipe (JSON); without it the options describe the terrain")
    p.add_argument("-o", "--output", action="append", required=True,
                   help="file to write, by extension: .png (16-bit height field), .glb/.obj/.ply (mesh), "
                   ".pov (POV-Ray scene; a height_field also writes <name>_height.png); repeat for several")
    g = p.add_argument_group("controls (without a recipe)")
    g.add_argument("--grid", choices=ifsforge.choices["grid"], help=f"default {t.grid}")
    g.add_argument("--controls", type=common.int_option(2, 4097), nargs=2, metavar=("ROWS", "COLUMNS"),
                   help=f"control lattice (default {d['controls']} {d['controls']}; circular: {d['circles']} circles "
                   f"of {d['circle_points']})")
    g.add_argument("--amplitude", type=common.float_option(0, 1e6), default=t.amplitude, help=f"random heights: {t.base} +- amplitude")
    g.add_argument("--heights-from", metavar="MAP.png", help="sample the control heights from a height map (an insert)")
    g.add_argument("--window", type=common.NUMBER, nargs=4, metavar=("X0", "Y0", "X1", "Y1"), default=list(t.window),
                   help="the part of the map the terrain covers, in [0, 1] image coordinates")
    g.add_argument("--low", type=common.NUMBER, default=t.low, help="height of map value 0")
    g.add_argument("--high", type=common.NUMBER, default=t.high, help="height of map value 1")
    g.add_argument("--radii", type=common.float_option(0, 1e6), nargs="+", help="circular: leading circle radii, from 0 (default to 2)")
    g.add_argument("--shift", type=common.float_option(0, 0.5), help="irregular/circular: random displacement amplitude (< 0.5 spacing)")
    extent = g.add_argument("--extent", type=common.float_option(0, 1e9, low_open=True), nargs=2, metavar=("X", "Y"),
                            help=f"horizontal extent in world units (default {t.size_x:g} {t.size_y:g}, for heights "
                            "around 0..1)")
    common.add_deprecated_alias(g, "--size", extent)  # --size is pixels in every other command
    r = p.add_argument_group("roughness (overrides the recipe's)")
    r.add_argument("--roughness", type=common.float_option(-1, 1), nargs="+", metavar="A22",
                   help="|a22| along the leading vectors, then across them (one value: both; default "
                   f"{d['roughness']:g}; 0: a bilinear surface through the controls)")
    r.add_argument("--signs", choices=ifsforge.choices["signs"], default=t.signs,
                   help="signs of the a22 factors (default random)")
    r.add_argument("--seed", type=common.SEED, default=0, help="seed of random controls, shifts and signs")
    o = p.add_argument_group("output")
    o.add_argument("--res", help="samples: N or WxH along x/y (circular: the height image's side; "
                   f"default the recipe's or {d['samples']})")
    o.add_argument("--palette", metavar="PALETTE.json", help="palette recipe (default: the recipe's)")
    o.add_argument("--preview", metavar="IMAGE.png", help="also write the height image colored by the palette")
    o.add_argument("--solid", action="store_true", help="meshes: close with walls and a floor (watertight)")
    common.add_up_argument(o)
    o.add_argument("--pov-shape", choices=ifsforge.choices["pov_shape"], default=pov.shape)
    o.add_argument("--pov-camera", choices=ifsforge.choices["pov_camera"], default=pov.camera)
    o.add_argument("--pov-flat", action="store_true", help="POV-Ray: no lights, the palette unshaded")
    o.add_argument("--povray-render", metavar="IMAGE.png", help="render the .pov output with POV-Ray")
    o.add_argument("--povray-size", default=f"{render.width}x{render.height}", help="WxH of the POV-Ray render")
    o.add_argument("--threads", type=common.THREADS, default=0, help="0: every core (the result never depends on it)")
    p.set_defaults(run=run)


def controls_from_options(args):
    """The core's one controls builder (the add-on uses it too: one seed, one terrain)."""
    options = dict(grid=args.grid, amplitude=args.amplitude, radii=args.radii, shift=args.shift, signs=args.signs)
    if args.controls:
        options["rows"], options["columns"] = args.controls
    if args.heights_from:
        options.update(height_map=ifsforge.read_png(args.heights_from), window=args.window, low=args.low,
                       high=args.high)
    if args.extent:
        options["size_x"], options["size_y"] = args.extent
    if args.roughness:
        options["roughness"] = roughness(args)
    return ifsforge.make_terrain_controls(args.seed, **options)


def roughness(args):
    if len(args.roughness) > 2:
        raise ifsforge.InputError("--roughness takes one or two values (along, across the leading vectors)")
    return args.roughness[0], args.roughness[-1]


def sample_counts(grid, controls, res, recipe):
    """(columns, rows) of the lattice and (width, height) of the height image."""
    circular = grid == "circular"
    if res is None and recipe is not None and recipe.columns:
        columns, rows = recipe.columns, recipe.rows
        if circular:
            return (columns, rows), (2 * rows - 1, 2 * rows - 1)
        return (columns, rows), (columns, rows)
    width, height = common.parse_size(res or str(ifsforge.terrain_defaults["samples"]), "--res")
    if circular:
        # The radius spans half the image; a circle gets at least pi * side angles, a multiple
        # of the controls per circle so that every control height is a sample.
        per_circle = len(controls.heights[0])
        side = max(width, height)
        angles = per_circle * math.ceil(math.pi * side / per_circle)
        return (angles, side // 2 + 1), (side, side)
    return (width, height), (width, height)


def run(args):
    for path in args.output:
        if os.path.splitext(path)[1].lower() not in OUTPUTS:
            raise ifsforge.InputError(f"cannot write '{path}': terrain outputs end in {', '.join(OUTPUTS)}")
        common.ensure_output_folder(path)
    for path in filter(None, [args.preview, args.povray_render]):
        common.ensure_output_folder(path)
    scenes = [p for p in args.output if p.lower().endswith(".pov")]
    if args.povray_render and not scenes:
        raise ifsforge.InputError("--povray-render needs a .pov output")

    recipe = None
    if args.recipe:
        given = [name for name in ("grid", "controls", "heights_from", "radii", "shift", "extent")
                 if getattr(args, name) is not None]
        if given:
            raise ifsforge.InputError(f"--{given[0].replace('_', '-')} describes a terrain without a recipe; "
                                      "edit the recipe instead")
        recipe = ifsforge.read_terrain_recipe(args.recipe)
        controls, name = recipe.controls, recipe.name
        if args.roughness:
            ifsforge.set_roughness(controls, *roughness(args), args.signs, args.seed)
    else:
        controls, name = controls_from_options(args), "terrain"
    grid = controls.grid

    palette, palette_name = None, "terrain"
    if args.palette:
        palette_recipe = ifsforge.read_palette_recipe(args.palette)
        palette, palette_name = palette_recipe.make(), palette_recipe.name
    elif recipe is not None and recipe.palette is not None:
        palette, palette_name = recipe.palette.make(), recipe.palette.name

    (columns, rows), (width, height) = sample_counts(grid, controls, args.res, recipe)
    terrain = ifsforge.make_terrain(controls, columns, rows, threads=args.threads,
                                    progress=ProgressBar(f"terrain {name}"))
    print(f"{name}: {grid} grid, {len(controls.heights)} x {len(controls.heights[0])} controls, "
          f"{columns} x {rows} samples, heights {terrain.min_height:.6g} to {terrain.max_height:.6g}")
    control_rows, control_columns = len(controls.heights), len(controls.heights[0])
    intervals = control_columns if grid == "circular" else control_columns - 1
    if (columns - (grid != "circular")) % intervals or (rows - 1) % (control_rows - 1):
        print(f"note: the control heights fall between samples; sample counts with (columns - 1) a multiple "
              f"of {intervals} and (rows - 1) of {control_rows - 1} put every control height on a sample")

    image = None
    if grid == "regular":
        width, height = terrain.columns, terrain.rows
    # Every output or none: a failed write or POV-Ray render leaves no file of this command
    # (a scene's height image included).
    # Each scene is written and rendered in a private folder beside its height image, joins the
    # other outputs once they are all written, and its height image follows it.
    with contextlib.ExitStack() as stack:
        private = {p: stack.enter_context(common.scene_folder(p)) for p in scenes}
        staged = stack.enter_context(common.all_or_none(args.output + list(filter(None, [args.preview, args.povray_render]))))
        into = {**staged, **private}
        for path in args.output:
            ext = os.path.splitext(path)[1].lower()
            if ext == ".png":
                image = image if image is not None else terrain.height_image(width, height, args.threads)
                ifsforge.write_png(into[path], image, 16)
                print(f"{path}: 16-bit height field {width}x{height} "
                      f"(0 = {terrain.min_height:.6g}, 65535 = {terrain.max_height:.6g})")
            elif ext in MESHES:
                ifsforge.write_terrain_mesh(into[path], terrain, palette=palette, solid=args.solid, up=args.up,
                                            threads=args.threads)
                textured = " with the palette as base-color texture" if ext == ".glb" and palette else ""
                print(f"{path}: {'solid ' if args.solid else ''}mesh{textured}")
            else:
                w, h = common.parse_size(args.povray_size)
                written = ifsforge.write_terrain_pov(into[path], terrain, palette, shape=args.pov_shape,
                                                     camera=args.pov_camera, flat=args.pov_flat, aspect=w / h,
                                                     threads=args.threads, title=f"ifsforge terrain: {name}",
                                                     palette_name=palette_name)
                print(f"{path}: POV-Ray {args.pov_shape} scene" + (f" (+ {os.path.basename(written[1])})" if len(written) > 1 else ""))
        if args.preview:
            image = image if image is not None else terrain.height_image(width, height, args.threads)
            colored = ifsforge.apply_palette(image, palette, args.threads) if palette else image
            ifsforge.write_png(into[args.preview], colored, 8)
            print(f"{args.preview}: height image colored by the palette" if palette else
                  f"{args.preview}: height image (no palette)")
        if args.povray_render:
            w, h = common.parse_size(args.povray_size)
            ifsforge.render_povray(into[scenes[0]], into[args.povray_render], w, h)
            print(f"{args.povray_render}: POV-Ray render {w}x{h} of {scenes[0]}")
        for path, scene in private.items():
            os.replace(scene, staged[path])
