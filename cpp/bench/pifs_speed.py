#!/usr/bin/python3
"""PIFS encoding and decoding speed, and what the fast domain search loses (seed 3.3.2).

1. Search loss: photographs (python3-skimage; their top-left 256x256, as the exhaustive search
   costs every range against every domain and isometry) encoded at 50:1 with the tree search and
   with the exhaustive one; PSNR of each decode against the original and the difference.
2. Encoding thread sweep (512x512 gray camera, 512x512 colour astronaut, the astronaut tiled 4x4
   to 2048x2048): wall and CPU time per thread count (median of runs), and on 2 threads the
   serial share: called from Python with its Ctrl-C check, the calling thread only reports
   progress during the parallel steps (the workers do the jobs) and does every serial step
   itself, so its CPU time over the process's is the serial share, whatever the load.
3. Decoding on 1 and 2 threads at scales 1, 2 and 4 of 256², 512² and 2048² images, the runs
   interleaved.

    PYTHONPATH=build/python cpp/bench/pifs_speed.py [--runs 3] [--results FILE|-]

Times on a shared machine vary with its load (recorded with the table); CPU times much less.
"""
import argparse
import statistics
import time

import numpy as np
from skimage import data

import ifsforge

LOSS_IMAGES = ("camera", "astronaut", "coffee", "chelsea", "rocket")
LOSS_SIDE = 256
RATIO = 50


def psnr(a, b):
    return 10 * np.log10(1.0 / np.mean((np.asarray(a, np.float64) - b) ** 2))


def search_loss(out):
    out.print(f"\n| photo ({LOSS_SIDE}², {RATIO}:1) | tree PSNR | exhaustive PSNR | loss (dB) | tree CPU (s) | exhaustive CPU (s) |")
    out.print("|---|---:|---:|---:|---:|---:|")
    losses = []
    for name in LOSS_IMAGES:
        image = getattr(data, name)()[:LOSS_SIDE, :LOSS_SIDE]
        reference = image / 255.0
        cells = []
        for search in ("tree", "exhaustive"):
            start = time.process_time()
            code = ifsforge.pifs_encode(image, ratio=RATIO, search=search, threads=2)
            cells.append((psnr(code.decode(threads=2), reference), time.process_time() - start))
        (tree, tree_cpu), (full, full_cpu) = cells
        losses.append(full - tree)
        out.print(f"| {name} | {tree:.2f} | {full:.2f} | {full - tree:.2f} | {tree_cpu:.3f} | {full_cpu:.1f} |")
    out.print(f"\nMean loss of the tree search: {statistics.mean(losses):.2f} dB (largest {max(losses):.2f}).")


def timed(f, runs):
    """Median wall, median process CPU and median CPU of the calling thread over `runs` calls."""
    walls, cpus, callers = [], [], []
    for _ in range(runs):
        w, c, t = time.perf_counter(), time.process_time(), time.thread_time()
        f()
        walls.append(time.perf_counter() - w)
        cpus.append(time.process_time() - c)
        callers.append(time.thread_time() - t)
    return statistics.median(walls), statistics.median(cpus), statistics.median(callers)


def encode_sweep(out, runs):
    astronaut = data.astronaut()
    images = {"512² gray": data.camera(), "512² colour": astronaut, "2048² colour": np.tile(astronaut, (4, 4, 1))}
    out.print("\n| encode (50:1) | threads | wall (s) | CPU (s) | serial share |")
    out.print("|---|---:|---:|---:|---:|")
    for label, image in images.items():
        n = runs if image.shape[0] <= 512 else 1
        for threads in (1, 2, 3):
            wall, cpu, caller = timed(lambda: ifsforge.pifs_encode(image, ratio=RATIO, threads=threads), n)
            share = f"{caller / cpu:.1%}" if threads == 2 else ""
            out.print(f"| {label} | {threads} | {wall:.3f} | {cpu:.3f} | {share} |")


def decode_ab(out, runs):
    out.print("\n| decode (50:1) | scale | 1 thread wall (ms) | 2 threads wall (ms) | 1 thread CPU (ms) | 2 threads CPU (ms) |")
    out.print("|---|---:|---:|---:|---:|---:|")
    camera, astronaut = data.camera(), data.astronaut()
    images = {"256² gray": camera[:256, :256], "256² colour": astronaut[:256, :256], "512² gray": camera,
              "512² colour": astronaut, "2048² colour": np.tile(astronaut, (4, 4, 1))}
    for label, image in images.items():
        code = ifsforge.pifs_encode(image, ratio=RATIO)
        for scale in (1, 2, 4):
            samples = {1: [], 2: []}
            # Interleaved, each first every other time, so both see the same load and neither
            # always follows the other; the largest decodes (8192²) fewer times.
            for i in range(max(6, 3 * runs) if image.shape[0] <= 512 else 4):
                for threads in ((1, 2) if i % 2 == 0 else (2, 1)):
                    samples[threads].append(timed(lambda: code.decode(scale=scale, threads=threads), 1))
            med = {t: [statistics.median(s[i] for s in samples[t]) for i in (0, 1)] for t in (1, 2)}
            out.print(f"| {label} | {scale} | {1000 * med[1][0]:.1f} | {1000 * med[2][0]:.1f} | "
                      f"{1000 * med[1][1]:.1f} | {1000 * med[2][1]:.1f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=3, help="runs per timing (median); 2048² runs once")
    parser.add_argument("--parts", default="loss,encode,decode", help="which tables (comma-separated)")
    import results  # beside this script
    results.add_argument(parser)
    args = parser.parse_args()
    with results.Section("pifs_speed.py", args.results, "PIFS speed and search loss (pifs_speed.py)") as out:
        parts = args.parts.split(",")
        if "loss" in parts:
            search_loss(out)
        if "encode" in parts:
            encode_sweep(out, args.runs)
        if "decode" in parts:
            decode_ab(out, args.runs)


if __name__ == "__main__":
    main()
