"""ifsforge volume: a 3D system as an OpenVDB volume (and its iso-surface mesh)."""
import os
import time

import ifsforge
from ifsforge import cli_common as common
from ifsforge import distributed
from ifsforge import media
from ifsforge.progress import ProgressBar

MESH_EXTENSIONS = (".ply", ".obj", ".glb")


def register(subparsers):
    # Every default is the core's (VolumeOptions, VdbWriteOptions, IsoSurfaceOptions): written once, in C++.
    o, vdb, iso = ifsforge.VolumeOptions(), ifsforge.VdbWriteOptions(), ifsforge.IsoSurfaceOptions()
    p = subparsers.add_parser(
        "volume", help="render a 3D system to an OpenVDB volume (.vdb) and/or an iso-surface mesh",
        description="Render a 3D system (layout xyz, xyz+gray, xyz+alpha, xyz+rgb, xyz+hsi, ...) into a sparse "
        "voxel grid with one of the four volumetric renderers of the seed's Table 2, and write it as OpenVDB "
        "(FloatGrid density, Vec3fGrid color, FloatGrids gray/alpha) and/or as the iso-surface mesh of its "
        "occupancy (.ply, .obj, .glb).")
    common.add_system_argument(p)
    p.add_argument("-o", "--output", help="the .vdb file to write")
    p.add_argument("--mesh", help="also write the iso-surface as .ply, .obj or .glb")
    p.add_argument("--df3", help="also write the density as a POV-Ray density file (.df3, for media); a color "
                   "volume also gets its linear red, green and blue beside it (V_red.df3, V_green.df3, V_blue.df3)")
    p.add_argument("--df3-bits", type=int, default=8, choices=[8, 16, 32], help="bits per .df3 voxel (default 8)")
    p.add_argument("--pov", metavar="SCENE.pov", help="a POV-Ray scene of the --df3 files as media (colored "
                   "emission where the volume has color), seen from its box's diagonal")
    p.add_argument("--pov-density", type=common.float_option(0, 1e6), default=media.DENSITY,
                   help="the media's average density over the box, per world unit (default %(default)s)")
    p.add_argument("--pov-size", default="320x240", help="WxH the --pov camera is framed for (default %(default)s)")
    p.add_argument("--res", type=common.count_option(16384), default=o.resolution,
                   help="voxels along the longest side of the grid (default %(default)s)")
    p.add_argument("--bounds", type=common.NUMBER, nargs=6, metavar=("XMIN", "YMIN", "ZMIN", "XMAX", "YMAX", "ZMAX"),
                   help="the grid's world box (default: around the attractor, its box corners on voxel centres)")
    p.add_argument("--algorithm", "-a", default="prr",
                   help="prr (point recursive, default), ria (random iteration), dia (deterministic "
                   "iteration), eta (escape time)")
    p.add_argument("--density", default=o.density, choices=ifsforge.choices["density"],
                   help="what the density grid holds (default binary: 1 per occupied voxel)")
    p.add_argument("--depth", type=common.int_option(0, 64), default=o.depth,
                   help="prr: recursion depth; dia: rewriting levels (0: until occupancy stops changing)")
    p.add_argument("--iterations", type=common.int_option(0, 10**12), default=o.iterations, help="ria: points (0: until occupancy stops changing)")
    p.add_argument("--escape-bound", type=common.int_option(0, 10**6), default=o.escape_bound, help="eta: steps a voxel must survive (0: from --res)")
    p.add_argument("--escape-norm", default=o.escape_norm, choices=ifsforge.choices["escape_norm"], help="eta: Eq. 55 delta")
    p.add_argument("--escape-max", action="store_true", help="eta: try the largest delta first (Eq. 56)")
    p.add_argument("--seed", type=common.SEED, default=o.seed, help="ria: random seed")
    p.add_argument("--threads", type=common.THREADS, default=o.threads, help="0: every core (the volume never depends on it)")
    p.add_argument("--color-scale", default=vdb.color_scale, choices=ifsforge.choices["color_scale"],
                   help="channels to [0, 1]: auto keeps values already in [0, 1], else range (Eq. 101)")
    p.add_argument("--full-precision", action="store_true",
                   help="store color grids as 32-bit floats (default: 16-bit halves, error <= 2^-11)")
    p.add_argument("--compress", action="store_true", help="Blosc-compress the .vdb (about a third smaller, slower)")
    p.add_argument("--iso", type=common.float_option(0, 1, low_open=True), default=iso.iso, help="mesh: iso level of the occupancy (default %(default)s)")
    p.add_argument("--adaptivity", type=common.float_option(0, 1), default=iso.adaptivity, help="mesh: 0 (every voxel) .. 1 (merge flat areas)")
    common.add_up_argument(p)
    distributed.add_cluster_arguments(p)
    p.set_defaults(run=run)


def summarize(system, dims, voxel_size, algorithm, depth, occupied, start):
    nx, ny, nz = dims
    print(f"{system.name}: {nx}x{ny}x{nz} voxels of {voxel_size:.6g}, {algorithm} (depth {depth}), "
          f"{occupied:,} occupied, {time.perf_counter() - start:.2f} s")


def run(args):
    if not args.output and not args.mesh and not args.df3:
        raise ifsforge.InputError("nothing to write: give -o out.vdb, --mesh out.glb and/or --df3 out.df3")
    if args.df3:
        if not args.df3.lower().endswith(".df3"):
            raise ifsforge.InputError(f"--df3 expects a .df3 file, got '{args.df3}'")
        common.ensure_output_folder(args.df3)
    if args.pov:
        if not args.df3:
            raise ifsforge.InputError("--pov renders the --df3 files: give --df3 V.df3 too")
        if not args.pov.lower().endswith(".pov"):
            raise ifsforge.InputError(f"--pov expects a .pov file, got '{args.pov}'")
        common.ensure_output_folder(args.pov)
        width, height = common.parse_size(args.pov_size, "--pov-size")
    if args.output:
        if not args.output.lower().endswith(".vdb"):
            raise ifsforge.InputError(f"-o expects a .vdb file, got '{args.output}'")
        common.ensure_output_folder(args.output)
    if args.mesh:
        if not args.mesh.lower().endswith(MESH_EXTENSIONS):
            raise ifsforge.InputError(f"--mesh expects a .ply, .obj or .glb file, got '{args.mesh}'")
        common.ensure_output_folder(args.mesh)
    system = common.load_system(args.system)
    options = dict(resolution=args.res, bounds=args.bounds, density=args.density, depth=args.depth,
                   iterations=args.iterations, escape_bound=args.escape_bound, escape_norm=args.escape_norm,
                   escape_pick_max=args.escape_max, seed=args.seed, threads=args.threads,
                   progress=ProgressBar(f"volume {system.name}"))
    if args.output:
        # Only what shapes the volume: no thread count (the bytes never depend on it), no path.
        shown = {k: v for k, v in sorted(vars(args).items())
                 if k not in ("run", "command", "threads", "output", "mesh", "df3", "pov", "pov_density", "pov_size",
                              *distributed.CLUSTER_OPTIONS)}
        vdb = dict(metadata={"ifsforge_resolution": str(args.res),
                             "ifsforge_command": "ifsforge volume " + " ".join(f"{k}={v}" for k, v in shown.items())},
                   color_scale=args.color_scale, half=not args.full_precision, compress=args.compress)
    start = time.perf_counter()
    if args.output and not args.mesh and not args.df3:
        # The .vdb alone: straight from the render, a band at a time (2048^3 and beyond fit), and
        # atomically (the core writes beside the target and renames).
        with distributed.client_from_args(args) as client:
            made = distributed.render_volume_to_vdb(args.output, system, args.algorithm, client=client, **options, **vdb)
        summarize(system, made["dims"], made["voxel_size"], made["algorithm"], made["depth"], made["voxels"], start)
        print(f"{args.output}: {os.path.getsize(args.output):,} bytes")
        return
    with distributed.client_from_args(args) as client:
        volume = distributed.render_volume(system, args.algorithm, client=client, **options)
    summarize(system, volume.dims, volume.voxel_size, volume.algorithm, volume.depth, len(volume), start)
    # The mesh is built before anything is written, then the .vdb and the mesh are committed
    # together: an error or Ctrl-C leaves neither.
    mesh = None
    if args.mesh:
        mesh = ifsforge.volume_to_mesh(volume, iso=args.iso, adaptivity=args.adaptivity, color_scale=args.color_scale,
                                       progress=ProgressBar(f"mesh {system.name}"))
    df3_files = media.df3_paths(args.df3, volume) if args.df3 else []
    with common.all_or_none([path for path in (args.output, args.mesh, *df3_files, args.pov) if path]) as staged:
        if args.output:
            start = time.perf_counter()
            ifsforge.write_vdb(staged[args.output], volume, system=system, threads=args.threads, **vdb)
            print(f"{args.output}: {os.path.getsize(staged[args.output]):,} bytes, {time.perf_counter() - start:.2f} s")
        if args.mesh:
            ifsforge.write_mesh(staged[args.mesh], mesh["positions"], mesh["triangles"], normals=mesh["normals"],
                                colors=mesh["colors"], name=system.name, up=args.up)
            print(f"{args.mesh}: {len(mesh['positions']):,} vertices, {len(mesh['triangles']):,} triangles")
        if args.df3:
            media.write_df3_files(args.df3, volume, bits=args.df3_bits, targets=staged)
            for path in df3_files:
                print(f"{path}: {os.path.getsize(staged[path]):,} bytes")
        if args.pov:
            folder = os.path.dirname(os.path.abspath(args.pov))
            names = [os.path.relpath(os.path.abspath(path), folder) for path in df3_files]
            density = args.pov_density * media.per_world_unit(volume)
            text = media.scene(volume, names, density, width, height, title=system.name)
            ifsforge.write_bytes(staged[args.pov], text.encode("utf-8"))
            print(f"{args.pov}: media reading {', '.join(names)}")
