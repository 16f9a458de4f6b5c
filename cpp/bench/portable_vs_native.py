#!/usr/bin/python3
"""The hot paths of a native build (-DIFSFORGE_NATIVE=ON, -march=native) against the default
portable one (plain x86-64, vector kernels picked at run time), and the portable one forced onto
its baseline x86-64 chaos kernel (IFSFORGE_ISA=baseline): one representative Google Benchmark of
each path, every program pinned to one core, the builds alternated, best of the rounds. Compared
on the process's CPU time where the benchmark reports it (bench_render, bench_pifs), which a shared
machine's load disturbs less than wall time; elsewhere on wall time.

    /usr/bin/python3 cpp/bench/portable_vs_native.py --native build-native --portable build [--rounds 3]
"""
import argparse
import csv
import io
import os
import subprocess

import results

# (program, benchmark name regex, path, measure): one benchmark per hot path. "cpu_ms": the
# process's CPU time (a counter of bench_render); "cpu_time": Google Benchmark's, the process's
# under MeasureProcessCPUTime (bench_pifs; elsewhere only the calling thread's); "real_time": wall.
CASES = [
    ("bench_render", "ChaosFern1024/1/200000000", "chaos game, fern 1024²", "cpu_ms"),
    ("bench_render", "ChaosTetrahedron3D/1/", "chaos game, tetrahedron 3D", "cpu_ms"),
    ("bench_render", "PrrSierpinski4096/1/12", "PRR, Sierpinski 4096²", "cpu_ms"),
    ("bench_volume", "BM_PrrSample/fern_3d_192", "volume PRR, fern 192³", "real_time"),
    ("bench_volume", "BM_WriteVdb/256", ".vdb write, 256³", "real_time"),
    ("bench_terrain", "RegularTerrain/1000/1/", "terrain 1000²", "real_time"),
    ("bench_pifs", "Encode/3/512/1/", "PIFS encode, RGB 512²", "cpu_time"),
    ("bench_pifs", "Decode512/3/1/1/", "PIFS decode, RGB 512²", "cpu_time"),
    ("bench_vector", "Instances1M/1/", "vector instances, depth 10", "real_time"),
]
# The baseline chaos kernel only changes the chaos rows, so only they run a third time.
BASELINE_PROGRAMS = {"bench_render": "ChaosFern1024/1/200000000|ChaosTetrahedron3D/1/"}
CORE = 0  # one core, so every build's threads share the same single CPU


def run(build, program, pattern, isa=None):
    """{benchmark name: {measure: ms}} from one run of one benchmark program on one core."""
    path = results.program_path(program, build).resolve()
    env = dict(os.environ)
    env.pop("IFSFORGE_ISA", None)
    if isa:
        env["IFSFORGE_ISA"] = isa
    out = subprocess.run(["taskset", "-c", str(CORE), str(path), f"--benchmark_filter={pattern}",
                          "--benchmark_format=csv"], env=env, capture_output=True, text=True, check=True,
                         cwd=path.parent).stdout  # bench_volume finds the samples from its build folder
    start = out.find("name,")
    rows = {}
    for row in csv.DictReader(io.StringIO(out[start:])):
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[row["time_unit"]]
        name = row["name"].removesuffix("/real_time").removesuffix("/process_time")
        rows[name] = {"real_time": float(row["real_time"]) * scale, "cpu_time": float(row["cpu_time"]) * scale}
        if row.get("cpu_ms"):
            rows[name]["cpu_ms"] = float(row["cpu_ms"])
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--native", default="build-native")
    parser.add_argument("--portable", default="build")
    parser.add_argument("--rounds", type=int, default=3)
    results.add_argument(parser)
    args = parser.parse_args()
    programs = {}
    for program, pattern, _, _ in CASES:
        programs.setdefault(program, []).append(pattern)
    runs = [("native", args.native, None, {p: "|".join(v) for p, v in programs.items()}),
            ("portable", args.portable, None, {p: "|".join(v) for p, v in programs.items()}),
            ("portable, IFSFORGE_ISA=baseline", args.portable, "baseline", BASELINE_PROGRAMS)]
    best = {}
    for _ in range(args.rounds):  # alternated, so a change of load hits every build alike
        for label, build, isa, chosen in runs:
            for program, pattern in chosen.items():
                for name, times in run(build, program, pattern, isa).items():
                    for measure, ms in times.items():
                        best[(label, name, measure)] = min(ms, best.get((label, name, measure), ms))
    title = "Hot paths: native against portable build"
    with results.Section("portable_vs_native.py", args.results, title) as out:
        out.print(f"One representative benchmark per hot path, the program pinned to one core, best of "
                  f"{args.rounds} alternated rounds: ms of the measure named, and the portable build's time against the native one.")
        out.print()
        out.print("| path | benchmark | measure | native ms | portable ms | portable / native | baseline kernel / native |")
        out.print("| --- | --- | --- | ---: | ---: | ---: | ---: |")
        for program, pattern, path, measure in CASES:
            names = sorted({name for label, name, _ in best if label == "native" and name.startswith(pattern.rstrip("/"))})
            for name in names:
                native, portable = best[("native", name, measure)], best[("portable", name, measure)]
                baseline = best.get(("portable, IFSFORGE_ISA=baseline", name, measure))
                cell = f"{baseline / native:.2f}×" if baseline else "–"
                out.print(f"| {path} | {program} {name} | {measure} | {native:.0f} | {portable:.0f} | {portable / native:.2f}× | {cell} |")


if __name__ == "__main__":
    main()
