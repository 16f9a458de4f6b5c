#!/usr/bin/python3
"""Whole commands as users run them: each figure a fresh `ifsforge` process, timed from the
outside (wall time, peak memory and page faults of the child), on 1 and 2 threads, beside its
target. In-process figures come from the Google Benchmark programs (bench_render, bench_volume),
with their page faults, rates and targets (IN_PROCESS_TARGETS). Last, the fern and the Sierpinski
triangle against flam3-render as commands (flam3_side_by_side.py), when flam3-utils is installed.

    cpp/bench/bench_commands.py [--runs 3] [--quick]

--quick skips the 1024^3 volume and flam3. Needs the built ifsforge (build/python).
"""
import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import results

ROOT = Path(__file__).resolve().parents[2]
SYSTEMS = ROOT / "samples" / "systems"
ENV = dict(os.environ, PYTHONPATH=str(ROOT / "build" / "python"))
#: The ratio to flam3-render each thread count must reach, as commands.
FLAM3_TARGETS = {1: 20.0, 2: 35.0}


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


def figure(out, label, args, target, runs):
    """Median wall time of `runs` fresh processes (after one warm-up for the file cache)."""
    run_child(args)
    samples = [run_child(args) for _ in range(runs)]
    wall = statistics.median(s[0] for s in samples)
    peak = max(s[1] for s in samples)
    faults = statistics.median(s[2] for s in samples)
    verdict = "" if target is None else ("ok" if wall < target else "MISSED")
    target_text = "" if target is None else f"< {target:g} s"
    out.print(f"| {label} | {wall:.3f} s | {peak:,.0f} MB | {faults:,.0f} | {target_text} | {verdict} |")
    return wall


def in_process(program, filter_):
    """Google Benchmark rows (name, real time, unit, counters) of build/cpp/bench/PROGRAM
    matching FILTER."""
    path = results.program_path(program, ROOT / "build")
    out = subprocess.run([str(path), f"--benchmark_filter={filter_}", "--benchmark_format=csv"],
                         capture_output=True, text=True, cwd=path.parent).stdout
    lines = [line for line in out.splitlines() if line.startswith("name,") or line.startswith('"')]
    if not lines:
        return []
    header = [h.strip('"') for h in lines[0].split(",")]
    rows = []
    for line in lines[1:]:
        fields = dict(zip(header, line.split(",")))
        counters = {k: float(v) for k, v in fields.items() if k not in IGNORED_COLUMNS and v}
        rows.append((fields["name"].strip('"'), float(fields["real_time"]), fields["time_unit"], counters))
    return rows


#: Google Benchmark's own CSV columns (the rest are the benchmark's counters).
IGNORED_COLUMNS = {"name", "iterations", "real_time", "cpu_time", "time_unit", "bytes_per_second",
                   "items_per_second", "label", "error_occurred", "error_message"}

#: In-process figures with a target: name prefix -> (seconds below which, or points/s from which
#: the figure meets it; the target as printed).
IN_PROCESS_TARGETS = {
    "PrrSierpinski4096/2/12/": ("seconds", 0.050, "< 50 ms"),  # the seed's depth (3^12 leaves)
    "PrrSierpinski4096/2/0/": ("seconds", 0.050, "< 50 ms"),   # the default: pieces under a pixel
    "ChaosTetrahedron3D/1/": ("points/s", 200e6, ">= 200 M points/s per core"),
    "BM_TableTwo/ria": ("seconds", 0.4, "< 0.4 s"),
}


def in_process_verdict(name, real, unit, counters):
    """(target text, verdict) of an in-process row, or two empty strings."""
    for prefix, (what, limit, text) in IN_PROCESS_TARGETS.items():
        if name.startswith(prefix):
            if what == "points/s":
                ok = counters.get("points/s", 0.0) >= limit
            else:
                ok = real / {"ns": 1e9, "us": 1e6, "ms": 1e3, "s": 1.0}[unit] < limit
            return text, "ok" if ok else "MISSED"
    return "", ""


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="skip the 1024^3 volume")
    results.add_argument(parser)
    args = parser.parse_args()
    with results.Section("bench_commands.py", args.results, "Whole commands (bench_commands.py)") as out:
        report(args, out)


def report(args, out):
    fern, sierpinski = SYSTEMS / "barnsley_fern.json", SYSTEMS / "sierpinski_triangle.json"
    pyramid = SYSTEMS / "volume_sierpinski_pyramid_rgb.json"
    with tempfile.TemporaryDirectory() as tmp:
        out.print("| command (fresh process) | wall (median) | peak memory | page faults | target | |")
        out.print("| --- | ---: | ---: | ---: | --- | --- |")
        figure(out, "`info sierpinski_triangle.json`", ["info", sierpinski], 0.150, args.runs)
        figure(out, "`render` of 1,024 points", ["render", fern, "-o", f"{tmp}/p.png", "--iterations", 1024,
                                                  "--size", 256], 0.150, args.runs)
        for threads in (1, 2):
            figure(out, f"fern 1024², 104,857,600 points, {threads} thread(s)",
                   ["render", fern, "-o", f"{tmp}/f.png", "--size", 1024, "--iterations", 104857600,
                    "--threads", threads], None, args.runs)
            figure(out, f"PRR Sierpinski 4096² to PNG, {threads} thread(s)",
                   ["render", sierpinski, "-a", "prr", "--size", 4096, "-o", f"{tmp}/s.png",
                    "--threads", threads], None, args.runs)
            figure(out, f"6D pyramid 512³ to `.vdb`, {threads} thread(s)",
                   ["volume", pyramid, "--res", 512, "-o", f"{tmp}/v.vdb", "--threads", threads],
                   1.0 if threads == 2 else None, args.runs)
            if not args.quick:
                figure(out, f"6D pyramid 1024³ to `.vdb`, {threads} thread(s)",
                       ["volume", pyramid, "--res", 1024, "-o", f"{tmp}/v.vdb", "--threads", threads],
                       6.0 if threads == 2 else None, 1)
    out.print()
    out.print("| in process (Google Benchmark) | real time | page faults | points/s | target | |")
    out.print("| --- | ---: | ---: | ---: | --- | --- |")
    for program, filter_ in (("bench_render", "PrrSierpinski4096|ChaosFern1024|ChaosTetrahedron3D"),
                             ("bench_volume", "PrrToVdb/(256|512)|TableTwo/")):
        for name, real, unit, counters in in_process(program, filter_):
            faults = f"{counters['faults']:,.0f}" if "faults" in counters else ""
            rate = f"{counters['points/s'] / 1e6:,.0f} M" if "points/s" in counters else ""
            target, verdict = in_process_verdict(name, real, unit, counters)
            out.print(f"| {program} {name} | {real:.1f} {unit} | {faults} | {rate} | {target} | {verdict} |")
    if args.quick or not shutil.which("flam3-render"):
        return
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from flam3_side_by_side import side_by_side
    out.print()
    out.print("| against flam3-render, 210 M samples at 1024² (commands) | flam3 | ifsforge | ratio | target | |")
    out.print("| --- | ---: | ---: | ---: | --- | --- |")
    with tempfile.TemporaryDirectory() as tmp:
        for threads, target in FLAM3_TARGETS.items():
            for name in ("fern", "sierpinski"):
                flam3, ours = side_by_side(name, threads, args.runs, folder=tmp)
                verdict = "ok" if flam3 / ours >= target else "MISSED"
                out.print(f"| {name}, {threads} thread(s) | {flam3:.3f} s | {ours:.3f} s | {flam3 / ours:.1f}x | "
                          f">= {target:g}x | {verdict} |")


if __name__ == "__main__":
    main()
