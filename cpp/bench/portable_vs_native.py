#!/usr/bin/python3
"""The chaos game of a native build (-march=native) against a portable one (-DIFSFORGE_PORTABLE=ON,
vector kernels picked at run time), and the portable one forced onto its baseline x86-64 kernel
(IFSFORGE_ISA=baseline): bench_render's chaos rows from each, alternated, best of the rounds.

    /usr/bin/python3 cpp/bench/portable_vs_native.py --native build --portable build-portable [--rounds 3]
"""
import argparse
import os
import subprocess
import sys
from pathlib import Path

import results

CASES = "ChaosFern1024/1/200000000|ChaosTetrahedron3D/1"


def run(build, isa=None):
    """{benchmark: (wall ms, CPU ms of the process)} from one run of bench_render."""
    program = Path(build) / "cpp" / "bench" / "bench_render"
    if not program.exists():
        sys.exit(f"{program} does not exist: build bench_render in {build} first")
    env = dict(os.environ)
    env.pop("IFSFORGE_ISA", None)
    if isa:
        env["IFSFORGE_ISA"] = isa
    out = subprocess.run([str(program), f"--benchmark_filter={CASES}", "--benchmark_format=csv"], env=env,
                         capture_output=True, text=True, check=True).stdout
    lines = [line for line in out.splitlines() if line.startswith("name,") or line.startswith('"')]
    header = [h.strip('"') for h in lines[0].split(",")]
    rows = {}
    for line in lines[1:]:
        row = dict(zip(header, line.split(",")))
        rows[row["name"].strip('"')] = (float(row["real_time"]), float(row["cpu_ms"]))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--native", default="build")
    parser.add_argument("--portable", default="build-portable")
    parser.add_argument("--rounds", type=int, default=3)
    results.add_argument(parser)
    args = parser.parse_args()
    builds = [("native build", args.native, None), ("portable build", args.portable, None),
              ("portable build, IFSFORGE_ISA=baseline", args.portable, "baseline")]
    best = {}
    for _ in range(args.rounds):  # alternated, so a change of load hits every build alike
        for label, build, isa in builds:
            for case, (wall, cpu) in run(build, isa).items():
                old = best.get((label, case))
                best[(label, case)] = (min(wall, old[0]), min(cpu, old[1])) if old else (wall, cpu)
    cases = sorted({case for _, case in best})
    with results.Section("portable_vs_native.py", args.results, "Chaos game: native against portable build") as out:
        out.print(f"bench_render, one thread, best of {args.rounds} alternated rounds: wall ms / CPU ms, "
                  "and CPU time against the native build.")
        out.print()
        out.print("| build | " + " | ".join(cases) + " |")
        out.print("| --- | " + " | ".join("---:" for _ in cases) + " |")
        for label, _, _ in builds:
            cells = []
            for case in cases:
                wall, cpu = best[(label, case)]
                cells.append(f"{wall:.0f} / {cpu:.0f} ({cpu / best[('native build', case)][1]:.2f}×)")
            out.print(f"| {label} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
