#!/usr/bin/python3
"""The `.vdb` writer against the disk: `ifsforge.write_vdb` of PRR's 3D + RGB pyramid (512³ and
1024³, halves, on 2 threads: plan, leaves, UUID, fsync and rename) beside `dd conv=fsync` of the
very same bytes to the same folder, the two alternated round by round (each first every other
round, both outputs removed before each), so that both see the same load and neither always
follows the other. Reported: medians of the wall times and of the writer's time over dd's within
each round; the writer's process CPU time (user + system, every thread) per voxel and its page
faults per output MB, which the load does not change much; the load before and after.

    PYTHONPATH=build/python cpp/bench/vdb_vs_dd.py [--sizes 512 1024] [--rounds 7] [--folder /tmp]
        [--results FILE|-]
"""
import argparse
import os
import resource
import statistics
import subprocess
import time
from pathlib import Path

import ifsforge

ROOT = Path(__file__).resolve().parents[2]
SYSTEM = ROOT / "samples" / "systems" / "volume_sierpinski_pyramid_rgb.json"


def usage():
    u = resource.getrusage(resource.RUSAGE_SELF)
    return u.ru_utime + u.ru_stime, u.ru_minflt + u.ru_majflt


def write(volume, system, path, threads):
    """(wall s, CPU s, page faults) of one write_vdb."""
    cpu, faults = usage()
    start = time.perf_counter()
    ifsforge.write_vdb(str(path), volume, system=system, threads=threads)
    wall = time.perf_counter() - start
    cpu_end, faults_end = usage()
    return wall, cpu_end - cpu, faults_end - faults


def dd(source, target):
    """Wall s of dd copying `source` (in the page cache: just written) to `target` with fsync."""
    start = time.perf_counter()
    subprocess.run(["dd", f"if={source}", f"of={target}", "bs=4M", "conv=fsync", "status=none"], check=True)
    return time.perf_counter() - start


def remove(*paths):
    for p in paths:
        p.unlink(missing_ok=True)


def measure(out, system, size, rounds, threads, folder):
    volume = ifsforge.render_volume(system, "prr", size)
    path = folder / f"ifsforge_vdb_vs_dd_{os.getpid()}_{size}.vdb"
    plain = folder / f"ifsforge_vdb_vs_dd_{os.getpid()}_{size}.plain"
    try:
        write(volume, system, path, threads)  # warm: the sRGB table, the first calls
        size_bytes = path.stat().st_size
        writes, copies = [], []
        for r in range(rounds):
            for step in (("vdb", "dd") if r % 2 == 0 else ("dd", "vdb")):
                remove(plain) if step == "dd" else remove(path)
                os.sync()  # neither pays for the other's leftovers
                if step == "vdb":
                    writes.append(write(volume, system, path, threads))
                else:
                    copies.append(dd(path, plain))
        assert path.stat().st_size == size_bytes and plain.stat().st_size == size_bytes
    finally:
        remove(path, plain)
    mb = size_bytes / 1e6
    wall = statistics.median(w[0] for w in writes)
    ceiling = statistics.median(copies)
    ratio = statistics.median(w[0] / c for w, c in zip(writes, copies))
    cpu = statistics.median(w[1] for w in writes)
    faults = statistics.median(w[2] for w in writes)
    out.print(f"| {size}³ pyramid, {len(volume) / 1e6:.1f} M voxels | {mb:.1f} MB | {wall:.3f} s, {mb / wall:.0f} MB/s | "
              f"{ceiling:.3f} s, {mb / ceiling:.0f} MB/s | {ratio:.2f}× | {cpu * 1e3:.0f} ms, "
              f"{cpu * 1e9 / len(volume):.1f} ns/voxel | {faults / mb:.1f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    parser.add_argument("--rounds", type=int, default=7, help="rounds per size (medians)")
    parser.add_argument("--threads", type=int, default=2, help="the writer's threads")
    parser.add_argument("--folder", default="/tmp", help="where both write (the same disk for both)")
    import results  # beside this script
    results.add_argument(parser)
    args = parser.parse_args()
    system = ifsforge.load(str(SYSTEM))
    load_before = os.getloadavg()[0]
    with results.Section("vdb_vs_dd.py", args.results, "The .vdb writer against dd (vdb_vs_dd.py)") as out:
        out.print(f"{args.rounds} rounds per size, writer on {args.threads} threads, both into {args.folder}; "
                  "medians. Writer / dd: the writer's wall time over dd's in the same round (1× is disk speed).")
        out.print("")
        out.print("| volume | file | `write_vdb` (fsync, rename) | `dd bs=4M conv=fsync` | writer / dd | writer CPU "
                  "| page faults per MB |")
        out.print("| --- | ---: | ---: | ---: | ---: | ---: | ---: |")
        for size in args.sizes:
            measure(out, system, size, args.rounds, args.threads, Path(args.folder))
        out.print("")
        out.print(f"Load (1-minute average) {load_before:.1f} before, {os.getloadavg()[0]:.1f} after.")


if __name__ == "__main__":
    main()
