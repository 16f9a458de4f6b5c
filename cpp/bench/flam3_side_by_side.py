#!/usr/bin/python3
"""Random iteration of the Barnsley fern and the Sierpinski triangle, ifsforge against flam3
(Debian's flam3-utils, the reference fractal-flame renderer), at the same number of samples:
1024x1024, `quality` samples per pixel. The two programs alternate run by run; the report is
the ratio of the medians. Both are timed end to end as commands that write an image (Python
start-up and PNG encoding included), and ifsforge's renderer alone is timed in process too.

    cpp/bench/flam3_side_by_side.py [--runs 5] [--quality 200] [--threads 1]

Needs `flam3-render` (apt-get install flam3-utils) and the built ifsforge (PYTHONPATH=build/python).
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

ROOT = Path(__file__).resolve().parents[2]
FLAMES = Path(__file__).resolve().parent / "data" / "flam3"
SYSTEMS = {"fern": ROOT / "samples/systems/barnsley_fern.json",
           "sierpinski": ROOT / "samples/systems/sierpinski_triangle.json"}


def timed(command, env=None):
    start = time.perf_counter()
    subprocess.run(command, check=True, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def render_only(system, samples, threads):
    sys.path.insert(0, str(ROOT / "build" / "python"))
    import ifsforge
    ifs = ifsforge.read_json(str(system))
    start = time.perf_counter()
    ifsforge.render(ifs, "chaos", 1024, iterations=samples, threads=threads)
    return time.perf_counter() - start


def side_by_side(name, threads, runs, quality=200, folder="/tmp"):
    """Medians of flam3-render and of the ifsforge command over `runs` alternating runs of system
    `name` (SYSTEMS), in seconds."""
    samples = quality * 1024 * 1024
    python_env = dict(os.environ, PYTHONPATH=str(ROOT / "build" / "python"))
    flam3_env = dict(os.environ, nthreads=str(threads), qs=str(quality), format="ppm",
                     **{"in": str(FLAMES / f"{name}_de0.flame"), "out": f"{folder}/{name}.ppm"})
    ours = ["/usr/bin/python3", "-m", "ifsforge", "render", str(SYSTEMS[name]), "-o", f"{folder}/{name}.png",
            "--size", "1024", "--iterations", str(samples), "--threads", str(threads)]
    flam3_times, our_times = [], []
    for _ in range(runs):
        flam3_times.append(timed(["flam3-render"], flam3_env))
        our_times.append(timed(ours, python_env))
    return statistics.median(flam3_times), statistics.median(our_times)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--quality", type=int, default=200, help="samples per pixel")
    parser.add_argument("--threads", type=int, default=1)
    import results  # beside this script
    results.add_argument(parser)
    args = parser.parse_args()
    with results.Section(f"flam3_side_by_side.py --threads {args.threads}", args.results,
                         f"Against flam3, {args.threads} thread(s) (flam3_side_by_side.py)",
                         preformatted=True) as out:
        report(args, out)


def report(args, out):
    if not shutil.which("flam3-render"):
        sys.exit("flam3-render is missing: apt-get install flam3-utils")
    samples = args.quality * 1024 * 1024
    out.print(f"{samples / 1e6:.0f} M samples into 1024x1024, {args.threads} thread(s), {args.runs} runs each")
    with tempfile.TemporaryDirectory() as tmp:
        for name, system in SYSTEMS.items():
            f, o = side_by_side(name, args.threads, args.runs, args.quality, tmp)
            r = statistics.median(render_only(system, samples, args.threads) for _ in range(args.runs))
            out.print(f"{name:11s} flam3 {f:7.3f} s ({samples / f / 1e6:6.1f} M samples/s) | ifsforge command "
                      f"{o:7.3f} s ({samples / o / 1e6:6.1f} M/s, {f / o:5.1f}x) | ifsforge render() {r:6.3f} s "
                      f"({samples / r / 1e6:7.1f} M/s, {f / r:5.1f}x)")


if __name__ == "__main__":
    main()
