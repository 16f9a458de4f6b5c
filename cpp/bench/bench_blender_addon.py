#!/usr/bin/python3
"""Benchmark of the Blender add-on at production sizes, measured inside real Blender, end to
end as the panel's buttons run them (core work, then the datablock fill on the main thread):
  terrain 1025^2 (target < 1.5 s) and 4097^2 (< 15 s), 256^3 iso-surfaces (< 3 s; the Sierpinski
  tetrahedron, and the Menger sponge with ten times the faces),
  160 000 instances (Menger sponge at depth 4, < 0.5 s), and the viewport preview of 200 000
  points after a parameter change (<= 30 ms; compute only: background Blender has no GPU).
Run:  /usr/bin/python3 cpp/bench/bench_blender_addon.py [--build build] [--repeat 3] [--no-4097]
It starts `blender -b --factory-startup` on itself and prints a table and a JSON line."""
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
TARGETS = {"terrain 1025": 1.5, "terrain 4097": 15.0, "iso-surface 256 tetrahedron": 3.0,
           "iso-surface 256 menger": 3.0, "instances 160k": 0.5,
           "preview 200k": 0.030}


def outside_blender():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default=str(ROOT / "build"), help="build folder holding python/ifsforge")
    parser.add_argument("--blender", default="blender")
    parser.add_argument("--repeat", type=int, default=3, help="runs per case (the median is reported)")
    parser.add_argument("--no-4097", dest="big", action="store_false", help="skip the 4097^2 terrain")
    import results  # beside this file; only outside Blender
    results.add_argument(parser)
    args = parser.parse_args()
    out = Path(os.environ.get("TMPDIR", "/tmp")) / "ifsforge_bench_blender_addon"
    result = subprocess.run([args.blender, "-b", "--factory-startup", "--python", __file__, "--",
                             str(Path(args.build) / "python"), str(args.repeat), str(int(args.big)), str(out)],
                            capture_output=True, text=True)
    results.record_blender_tables("bench_blender_addon.py", args.results,
                                  "Blender add-on at production sizes (bench_blender_addon.py)", result)


def inside_blender(python_path, repeat, big, out):
    import addon_utils
    import bpy
    sys.path[:0] = [python_path, str(ROOT / "blender_addon")]
    addon_utils.enable("ifsforge_addon", default_set=True, handle_error=None)
    from ifsforge_addon import preview

    context, scene = bpy.context, bpy.context.scene
    scene.ifsforge.cache_folder = str(out)
    settings, design = scene.ifsforge.settings, scene.ifsforge.system
    results = {"threads": os.cpu_count()}

    def timed(name, preset, operator, size, runs=repeat):
        for obj in context.selected_objects:
            obj.select_set(False)
        bpy.ops.ifsforge.load_preset(preset=preset)
        times = []
        for _ in range(runs):
            for obj in context.selected_objects:
                obj.select_set(False)
            start = time.perf_counter()
            operator()
            context.view_layer.update()  # the depsgraph evaluates the new datablock too
            times.append(time.perf_counter() - start)
            obj = context.active_object
            described = size(obj)
            bpy.data.objects.remove(obj)
        results[name] = {"size": described, "median_s": statistics.median(times),
                         "target_s": TARGETS[name]}

    print("| case | size | median s | target s |")
    print("|---|---|---|---|")
    settings.terrain_source = 'RANDOM'
    settings.terrain_resolution = 1025
    timed("terrain 1025", "barnsley_fern.json", bpy.ops.ifsforge.generate_terrain,
          lambda obj: f"{len(obj.data.vertices):,} vertices")
    if big:
        settings.terrain_resolution = 4097
        timed("terrain 4097", "barnsley_fern.json", bpy.ops.ifsforge.generate_terrain,
              lambda obj: f"{len(obj.data.vertices):,} vertices", runs=1)
    settings.volume_resolution = 256
    for name, preset in (("tetrahedron", "sierpinski_tetrahedron.json"), ("menger", "menger_sponge.json")):
        timed(f"iso-surface 256 {name}", preset, bpy.ops.ifsforge.generate_mesh,
              lambda obj: f"{len(obj.data.polygons):,} faces, {len(obj.data.loop_triangles):,} triangles")
    settings.instance_depth = 4
    timed("instances 160k", "menger_sponge.json", bpy.ops.ifsforge.generate_instances,
          lambda obj: f"{len(obj.data.vertices):,} points")

    bpy.ops.ifsforge.load_preset(preset="menger_sponge.json")
    scene.ifsforge.preview.count = 200000
    preview.current.update(context)
    times = []
    for k in range(30):
        start = time.perf_counter()
        design.maps[k % len(design.maps)].rotation[0] += 0.5  # one step of a drag
        cloud = preview.current.update(context)
        times.append(time.perf_counter() - start)
        assert cloud is not None and cloud.count == 200000
    results["preview 200k"] = {"size": "200,000 points", "median_s": statistics.median(times),
                               "target_s": TARGETS["preview 200k"]}
    for name, row in results.items():
        if name != "threads":
            print(f"| {name} | {row['size']} | {row['median_s']:.3f} | {row['target_s']} |")
    print("BENCH " + json.dumps(results))


if __name__ == "__main__":
    if importlib.util.find_spec("bpy") is None:  # plain Python: start Blender on this file
        outside_blender()
    else:
        argv = sys.argv[sys.argv.index("--") + 1:]
        inside_blender(argv[0], int(argv[1]), argv[2] == "1", Path(argv[3]))
        sys.stdout.flush()
        os._exit(0)
