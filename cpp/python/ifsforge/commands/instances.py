"""ifsforge instances: vector recursive rendering (seed 5.8.2) of a system into an instance list,
written as a POV-Ray scene (optionally rendered), SVG, glTF, numpy, address CSV or a PNG drawing."""
import argparse
import io
import os
import time

import numpy as np

import ifsforge
from ifsforge import cli_common as common
from ifsforge.progress import ProgressBar


def register(subparsers):
    # The defaults are the core's (InstanceOptions, PovSceneOptions, PovRenderOptions): written once, in C++.
    d, scene, pov = ifsforge.InstanceOptions(), ifsforge.PovSceneOptions(), ifsforge.PovRenderOptions()
    p = subparsers.add_parser(
        "instances", help="vector IFS: primitives placed by the maps (POV-Ray, SVG, glTF, numpy)",
        description="Push a vector through the maps to every address of depth L (vector recursive "
        "rendering, seed 5.8.2) and place a primitive at each leaf: position, full 3D frame, scale "
        "(Eq. 60-62), primitive (the k channel, Eq. 99/107) and color (the color channels, Eq. 101).")
    common.add_system_argument(p)
    g = p.add_argument_group("the instance list")
    g.add_argument("--depth", type=common.int_option(0, 64), default=d.depth, help="recursion depth L: N^L instances (0: largest L with N^L <= 50000)")
    g.add_argument("--primitive", default=",".join(d.primitives),
                   help="primitive, or a comma list the k channel picks from: line, circle, triangle, square "
                   "(each also -outline), sphere, box, cone, cylinder, torus, mesh:PATH (default %(default)s)")
    normalization = g.add_argument("--normalization", choices=ifsforge.choices["normalization"], default=d.normalization,
                                   help="proportional: d = sf |q1 - q0| (Eq. 60); constant: d = --length for all")
    common.add_deprecated_alias(g, "--normalisation", normalization)
    g.add_argument("--scale-factor", type=common.float_option(0, 1e6, low_open=True), default=d.scale_factor, help="sf of Eq. 60 (default %(default)s)")
    g.add_argument("--length", type=common.float_option(0, 1e9), default=d.length, help="constant normalization: the vector length (0: automatic)")
    g.add_argument("--base-point", type=common.NUMBER, nargs="+", metavar="X",
                   help="q0 in every channel (default: the centre of the attractor's bounds)")
    g.add_argument("--base-vector", type=common.NUMBER, nargs="+", metavar="X",
                   help="q1 - q0, spatial (default: (R, 0[, 0]), R the half-diagonal of the bounds)")
    g.add_argument("--base-up", type=common.NUMBER, nargs=3, metavar="X", help="3D: the frame's second axis (default 0 1 0)")
    g.add_argument("--min-probability", type=common.float_option(0, 1), default=d.min_probability,
                   help="pv of the TSA (5.7): a branch less probable than this stops early")
    color_by = g.add_argument("--color-by", choices=ifsforge.choices["color_source"], default=d.color_source,
                              help="auto: the color channels if the layout has them, else the first map of the address")
    common.add_deprecated_alias(g, "--colour-by", color_by)
    g.add_argument("--color", type=common.float_option(0, 1), nargs="+", metavar="V", default=list(d.color[:3]),
                   help="--color-by constant: R G B [A] in [0, 1]")
    g.add_argument("--colors-as-given", action="store_true",
                   help="take the color channels as they are (clamped to [0, 1]) instead of stretching each "
                   "over its range on the attractor (Eq. 101)")
    o = p.add_argument_group("outputs (any number)")
    o.add_argument("--pov", metavar="SCENE.pov", help="POV-Ray 3.7 scene (ifsforge.inc is written beside it)")
    o.add_argument("--render", metavar="IMAGE.png", help="render the --pov scene with POV-Ray")
    o.add_argument("--svg", metavar="FILE.svg", help="SVG (2D systems)")
    o.add_argument("--gltf", metavar="FILE.glb", help="binary glTF, one node per instance (Blender)")
    common.add_up_argument(o)
    o.add_argument("--npy", metavar="FILE.npy", help="numpy structured array (numpy.load)")
    o.add_argument("--csv", metavar="FILE.csv", help="the addresses: index,address,length,probability")
    o.add_argument("--png", metavar="IMAGE.png", help="a picture drawn without POV-Ray (2D vector IFS; 3D preview)")
    s = p.add_argument_group("scene and pictures")
    s.add_argument("--size", default=None, help=f"WxH of the render/picture the camera is framed for (default {pov.width}x{pov.height})")
    s.add_argument("--view", type=common.NUMBER, nargs=2, metavar=("YAW", "PITCH"),
                   help="3D: degrees, as `render --view` (default: the system's, else 30 25)")
    s.add_argument("--orthographic", action="store_true", help="POV-Ray: orthographic camera (the render --view projection)")
    s.add_argument("--fov", type=common.float_option(0, 180, low_open=True), default=scene.fov, help="POV-Ray: horizontal field of view (degrees)")
    s.add_argument("--floor", action=argparse.BooleanOptionalAction, default=None, help="POV-Ray: a floor plane (default: 3D systems)")
    s.add_argument("--sky", action=argparse.BooleanOptionalAction, default=None, help="POV-Ray: a sky sphere (default: 3D systems)")
    s.add_argument("--background", type=common.float_option(0, 1), nargs=3, metavar="V", default=list(scene.background),
                   help="background color without sky (default %(default)s)")
    s.add_argument("--quality", choices=ifsforge.choices["quality"], default=scene.quality,
                   help="POV-Ray: draft (no shadows), normal, high (soft shadows, radiosity)")
    s.add_argument("--bounded-by", action="store_true",
                   help="POV-Ray: add bounded_by to the union (POV-Ray 3.7 then traces far slower)")
    s.add_argument("--antialias", type=common.float_option(0, 3), default=pov.antialias, help="POV-Ray's +A threshold (0: off)")
    p.add_argument("--threads", type=common.THREADS, default=d.threads, help="0: every core (the output never depends on it)")
    p.set_defaults(run=run)


def atomic_save_npy(path, array):
    buffer = io.BytesIO()
    np.save(buffer, array)
    ifsforge.write_bytes(path, buffer.getvalue())


def run(args):
    if args.render and not args.pov:
        raise ifsforge.InputError("--render renders the --pov scene: give --pov SCENE.pov too")
    outputs = [f for f in (args.pov, args.render, args.svg, args.gltf, args.npy, args.csv, args.png) if f]
    for path in outputs:
        common.ensure_output_folder(path)
    if len(args.color) not in (3, 4):
        raise ifsforge.InputError(f"--color expects R G B or R G B A, got {len(args.color)} numbers")
    system = common.load_system(args.system)
    frame = ifsforge.PovRenderOptions()
    width, height = common.parse_size(args.size) if args.size else (frame.width, frame.height)
    view = args.view or system.render_defaults.get("view") or tuple(ifsforge.DrawOptions().view)

    start = time.perf_counter()
    instances = ifsforge.instances(
        system, depth=args.depth, primitives=args.primitive, normalization=args.normalization,
        scale_factor=args.scale_factor, length=args.length, base_point=args.base_point,
        base_vector=args.base_vector, base_up=args.base_up, min_probability=args.min_probability,
        color_source=args.color_by, color=list(args.color) + [1.0] * (4 - len(args.color)),
        normalize_colors=not args.colors_as_given, threads=args.threads, progress=ProgressBar(f"instances {system.name}"))
    names = ", ".join(p.name for p in instances.primitives)
    print(f"{system.name}: {len(instances)} instances of {names}, depth {instances.addresses.depth}, "
          f"{time.perf_counter() - start:.2f} s")

    # Several files: all of them or none (a failure or Ctrl-C on the last keeps no other). The
    # scene is written and rendered in a private folder beside ifsforge.inc, joins the other
    # outputs once they are all written, and ifsforge.inc follows it.
    with common.scene_folder(args.pov) as scene, common.all_or_none(outputs) as staged:
        if args.pov:
            ifsforge.write_pov_scene(
                scene, instances, width=width, height=height, view=view, orthographic=args.orthographic,
                fov=args.fov, floor=args.floor, sky=args.sky, background=args.background, quality=args.quality,
                bounded_by=args.bounded_by, threads=args.threads, progress=ProgressBar("POV-Ray scene"))
            print(f"{args.pov}: POV-Ray 3.7 scene framed for {width}x{height} (+ ifsforge.inc)")
        if args.render:
            start = time.perf_counter()
            ifsforge.render_povray(scene, staged[args.render], width, height, antialias=args.antialias)
            print(f"{args.render}: rendered by POV-Ray in {time.perf_counter() - start:.1f} s")
        if args.svg:
            ifsforge.write_svg(staged[args.svg], instances, width=width,
                               background=None if args.background == [1.0, 1.0, 1.0] else args.background)
            print(f"{args.svg}: SVG, {width} px wide")
        if args.gltf:
            ifsforge.write_gltf_instances(staged[args.gltf], instances, up=args.up)
            print(f"{args.gltf}: glTF, one node per instance")
        if args.npy:
            array = instances.to_numpy()
            atomic_save_npy(staged[args.npy], array)
            print(f"{args.npy}: numpy structured array, {array.dtype.itemsize} bytes per instance")
        if args.csv:
            ifsforge.write_address_csv(staged[args.csv], instances.addresses)
            print(f"{args.csv}: {len(instances)} addresses")
        if args.png:
            image = ifsforge.draw_instances(instances, width, height, view=view,
                                            background=list(args.background) + [1.0], threads=args.threads)
            ifsforge.write_png(staged[args.png], image)
            print(f"{args.png}: {width}x{height} drawing")
        if args.pov:
            os.replace(scene, staged[args.pov])
    if not outputs:
        print("no output asked: add --pov, --svg, --gltf, --npy, --csv or --png")
