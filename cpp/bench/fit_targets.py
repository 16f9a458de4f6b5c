"""Benchmark of `ifsforge fit`: held-out classic attractors and a natural silhouette.

Each target is a 256-pixel picture (the attractors rendered by the chaos game, skimage's horse
as it is); the fit runs with a 60 s time limit on the given threads. Prints, per target, the
IoU of the fitted attractor with the target, the Hausdorff distance (Eq. 12, pixels) between
the fitted attractor drawn at the target's size and the target, the collage distance
(Eq. 41) and the time.  Run: PYTHONPATH=build/python python3 cpp/bench/fit_targets.py [--threads 2]
"""
import argparse
import json
import time

import numpy as np

import ifsforge

CLASSIC = {
    # name: (maps, JSON maps) -- none of them is a sample system the fit could have seen.
    "sierpinski": (3, [{"scale": 0.5, "translation": [0, 0]}, {"scale": 0.5, "translation": [0.5, 0]},
                       {"scale": 0.5, "translation": [0.25, 0.5]}]),
    "four-corner dust": (4, [{"scale": 0.4, "translation": [x, y]} for x in (0, 0.6) for y in (0, 0.6)]),
    "dragon": (2, [{"matrix": [[0.5, -0.5], [0.5, 0.5]], "offset": [0, 0]},
                   {"matrix": [[-0.5, -0.5], [0.5, -0.5]], "offset": [1, 0]}]),
}


def classic_target(maps, size=256):
    system = ifsforge.parse_json(json.dumps({"format": "ifsforge/1", "name": "target", "layout": "xy",
                                             "maps": maps}))
    return np.asarray(ifsforge.render(system, "chaos", size, size, binary=True).mask, bool)


def horse_target():
    import skimage.data
    horse = ~skimage.data.horse()  # skimage's horse is False on True: the shape is the False pixels
    # 256 pixels along the long side, like the other targets (nearest neighbour).
    h, w = horse.shape
    side = 256 / max(h, w)
    rows = (np.arange(int(h * side)) / side).astype(int)
    cols = (np.arange(int(w * side)) / side).astype(int)
    return horse[rows][:, cols]


def targets():
    out = [(name, classic_target(maps), n) for name, (n, maps) in CLASSIC.items()]
    out.append(("horse", horse_target(), 10))
    return out


def drawn(system, shape):
    """The fitted attractor drawn by `render` at the target's size on its render.window."""
    raster = ifsforge.render(system, "chaos", shape[1], shape[0], binary=True,
                             window=system.render_defaults["window"])
    return np.asarray(raster.mask, bool)


def evaluate(name, target, maps, threads=2, seed=0, time_limit=60.0):
    start = time.perf_counter()
    result = ifsforge.fit(target, maps=maps, time_limit=time_limit, seed=seed, threads=threads)
    seconds = time.perf_counter() - start
    system = result["system"]
    picture = drawn(system, target.shape)
    iou = float((picture & target).sum() / (picture | target).sum())
    return {"target": name, "maps": maps, "iou": iou, "hausdorff_pixels": ifsforge.hausdorff_distance(picture, target),
            "collage_pixels": ifsforge.collage_distance(system, target)["distance_pixels"], "seconds": seconds,
            "time_limited": result["time_limited"], "system": system, "fit": picture}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    print(f"{'target':18} {'maps':>4} {'IoU':>6} {'Hausdorff px':>12} {'collage px':>10} {'time s':>7}")
    for name, target, maps in targets():
        r = evaluate(name, target, maps, args.threads, args.seed)
        print(f"{name:18} {maps:4d} {r['iou']:6.3f} {r['hausdorff_pixels']:12.2f} {r['collage_pixels']:10.2f} "
              f"{r['seconds']:7.1f}" + (" (time limit)" if r["time_limited"] else ""), flush=True)


if __name__ == "__main__":
    main()
