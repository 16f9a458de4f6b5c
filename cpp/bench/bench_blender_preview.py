#!/usr/bin/python3
"""Benchmark of the Blender add-on's two speed targets, measured inside real Blender:
  1. the live preview: a map parameter changes -> the 200k preview points are ready
     (the add-on's own path: read the properties, build the system, ifsforge.preview_cloud);
     target <= 30 ms;
  2. a 256^3 volume generated as the panel's button does it (render, write the .vdb, load it
     into a Volume object with its material); target < 0.5 s.
Run:  /usr/bin/python3 cpp/bench/bench_blender_preview.py [--build build] [--repeat 30]
It starts `blender -b --factory-startup` on itself and prints a table and a JSON line.
The GPU upload of the points is not part of (1): background Blender has no GPU; the windowed
test (tests/blender/addon_gui.py) reports it."""
import argparse
import importlib.util
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def outside_blender():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(ROOT / "build"), help="build folder holding python/ifsforge")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--repeat", type=int, default=30, help="parameter changes per system")
    parser.add_argument("--volume-repeat", type=int, default=3)
    import results  # beside this file; only outside Blender
    results.add_argument(parser)
    args = parser.parse_args()
    out = Path(os.environ.get("TMPDIR", "/tmp")) / "ifsforge_bench_blender"
    result = subprocess.run([args.blender, "-b", "--factory-startup", "--python", __file__, "--",
                             str(Path(args.build) / "python"), str(args.repeat), str(args.volume_repeat), str(out)],
                            capture_output=True, text=True)
    results.record_blender_tables("bench_blender_preview.py", args.results,
                                  "Blender preview and panel volume (bench_blender_preview.py)", result)


def inside_blender(python_path, repeat, volume_repeat, out):
    import addon_utils
    import bpy
    sys.path[:0] = [python_path, str(ROOT / "blender_addon")]
    addon_utils.enable("ifsforge_addon", default_set=True, handle_error=None)
    import ifsforge
    from ifsforge_addon import preview, properties, state

    context, scene = bpy.context, bpy.context.scene
    scene.ifsforge.cache_folder = str(out)
    design = scene.ifsforge.system
    results = {"threads": os.cpu_count(), "preview": {}, "volume": {}}

    print("| preview (200k points) | maps | median ms | p95 ms | max ms | of which read+build ms |")
    print("|---|---|---|---|---|---|")
    for preset in ("barnsley_fern.json", "menger_sponge.json", "volume_coral_6d.json"):
        bpy.ops.ifsforge.load_preset(preset=preset)
        scene.ifsforge.preview.count = 200000
        preview.current.update(context)
        totals, builds = [], []
        for k in range(repeat):
            start = time.perf_counter()
            design.maps[k % len(design.maps)].rotation[0] += 0.5  # what a drag does, one step
            cloud = preview.current.update(context)
            totals.append(time.perf_counter() - start)
            assert cloud is not None and cloud.count == 200000
            start = time.perf_counter()
            state.Analysis(properties.read_record(design))
            builds.append(time.perf_counter() - start)
        totals.sort()
        row = {"maps": len(design.maps), "median_ms": 1e3 * statistics.median(totals),
               "p95_ms": 1e3 * totals[int(0.95 * (len(totals) - 1))], "max_ms": 1e3 * totals[-1],
               "build_ms": 1e3 * statistics.median(builds)}
        results["preview"][preset] = row
        print(f"| {preset} | {row['maps']} | {row['median_ms']:.2f} | {row['p95_ms']:.2f} | {row['max_ms']:.2f} "
              f"| {row['build_ms']:.2f} |")

    print()
    print("| 256^3 volume from the panel | voxels | total s | render s | write s | Blender load s |")
    print("|---|---|---|---|---|---|")
    for preset in ("sierpinski_tetrahedron.json", "volume_sierpinski_pyramid_rgb.json"):
        for obj in context.selected_objects:
            obj.select_set(False)
        bpy.ops.ifsforge.load_preset(preset=preset)
        scene.ifsforge.settings.volume_resolution = 256
        system = state.system_of(design)
        totals = []
        for _ in range(volume_repeat):
            for obj in context.selected_objects:
                obj.select_set(False)
            start = time.perf_counter()
            bpy.ops.ifsforge.generate_volume()
            for grid in context.active_object.data.grids:  # the voxels themselves, not only the names
                grid.load()
            totals.append(time.perf_counter() - start)
        # The parts, measured the same way the generator runs them.
        start = time.perf_counter()
        volume = ifsforge.render_volume(system, "prr", 256)
        render = time.perf_counter() - start
        start = time.perf_counter()
        ifsforge.write_vdb(str(out / "part.vdb"), volume, system)
        write = time.perf_counter() - start
        obj = context.active_object
        start = time.perf_counter()
        obj.data.filepath = str(out / "part.vdb")
        obj.data.grids.load()
        for grid in obj.data.grids:
            grid.load()
        load = time.perf_counter() - start
        row = {"voxels": len(volume), "total_s": statistics.median(totals), "render_s": render, "write_s": write,
               "load_s": load}
        results["volume"][preset] = row
        print(f"| {preset} | {row['voxels']:,} | {row['total_s']:.3f} | {render:.3f} | {write:.3f} | {load:.3f} |")
    print("BENCH " + json.dumps(results))


if __name__ == "__main__":
    if importlib.util.find_spec("bpy") is None:  # plain Python: start Blender on this file
        outside_blender()
    else:
        argv = sys.argv[sys.argv.index("--") + 1:]
        inside_blender(argv[0], int(argv[1]), int(argv[2]), Path(argv[3]))
        sys.stdout.flush()
        os._exit(0)
