#!/usr/bin/python3
"""Whole commands as users run them: each figure a fresh `ifsforge` process, timed from the
outside (wall time, peak memory and page faults of the child), on 1 and 2 threads, beside its
target. In-process figures come from the Google Benchmark programs (bench_render, bench_volume).

    cpp/bench/bench_commands.py [--runs 3] [--quick]

--quick skips the 1024^3 volume. Needs the built ifsforge (build/python).
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SYSTEMS = ROOT / "samples" / "systems"
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "build" / "python"))


def run_child(args):
    """(wall seconds, peak RSS MB, minor + major page faults) of one fresh process."""
    start = time.perf_counter()
    child = subprocess.Popen(["/usr/bin/python3", "-m", "ifsforge", *map(str, args)], env=ENV,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    error = child.stderr.read().decode(errors="replace")
    child.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"ifsforge {' '.join(map(str, args))} failed:\n{error}")
    return wall, usage.ru_maxrss / 1024.0, usage.ru_minflt + usage.ru_majflt


def figure(label, args, target, runs):
    """Median wall time of `runs` fresh processes (after one warm-up for the file cache)."""
    run_child(args)
    samples = [run_child(args) for _ in range(runs)]
    wall = statistics.median(s[0] for s in samples)
    peak = max(s[1] for s in samples)
    faults = statistics.median(s[2] for s in samples)
    verdict = "" if target is None else ("ok" if wall < target else "MISSED")
    target_text = "" if target is None else f"< {target:g} s"
    print(f"| {label} | {wall:.3f} s | {peak:,.0f} MB | {faults:,.0f} | {target_text} | {verdict} |", flush=True)
    return wall


def in_process(program, filter_):
    """Google Benchmark rows (name, real time) of build/cpp/bench/PROGRAM matching FILTER."""
    path = ROOT / "build" / "cpp" / "bench" / program
    if not path.exists():
        return []
    out = subprocess.run([str(path), f"--benchmark_filter={filter_}", "--benchmark_format=csv"],
                         capture_output=True, text=True, cwd=path.parent).stdout
    rows = []
    for line in out.splitlines():
        if line.startswith('"'):
            fields = line.split(",")
            rows.append((fields[0].strip('"'), float(fields[2]), fields[4]))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="skip the 1024^3 volume")
    args = parser.parse_args()
    fern, sierpinski = SYSTEMS / "barnsley_fern.json", SYSTEMS / "sierpinski_triangle.json"
    pyramid = SYSTEMS / "volume_sierpinski_pyramid_rgb.json"
    with tempfile.TemporaryDirectory() as tmp:
        print("| command (fresh process) | wall (median) | peak memory | page faults | target | |")
        print("| --- | ---: | ---: | ---: | --- | --- |")
        figure("`info sierpinski_triangle.json`", ["info", sierpinski], 0.150, args.runs)
        figure("`render` of 1,024 points", ["render", fern, "-o", f"{tmp}/p.png", "--iterations", 1024,
                                             "--size", 256], 0.150, args.runs)
        for threads in (1, 2):
            figure(f"fern 1024², 104,857,600 points, {threads} thread(s)",
                   ["render", fern, "-o", f"{tmp}/f.png", "--size", 1024, "--iterations", 104857600,
                    "--threads", threads], None, args.runs)
            figure(f"PRR Sierpinski 4096² to PNG, {threads} thread(s)",
                   ["render", sierpinski, "-a", "prr", "--size", 4096, "-o", f"{tmp}/s.png",
                    "--threads", threads], None, args.runs)
            figure(f"6D pyramid 512³ to `.vdb`, {threads} thread(s)",
                   ["volume", pyramid, "--res", 512, "-o", f"{tmp}/v.vdb", "--threads", threads],
                   1.0 if threads == 2 else None, args.runs)
            if not args.quick:
                figure(f"6D pyramid 1024³ to `.vdb`, {threads} thread(s)",
                       ["volume", pyramid, "--res", 1024, "-o", f"{tmp}/v.vdb", "--threads", threads],
                       6.0 if threads == 2 else None, 1)
    print()
    print("| in process (Google Benchmark) | real time | |")
    print("| --- | ---: | --- |")
    for program, filter_ in (("bench_render", "PrrSierpinski4096|ChaosFern1024|ChaosTetrahedron3D"),
                             ("bench_volume", "PrrToVdb/(256|512)|TableTwo/")):
        for name, real, unit in in_process(program, filter_):
            print(f"| {program} {name} | {real:.1f} {unit} | |")


if __name__ == "__main__":
    main()
