"""Gallery items of the inverse problem (seed chapter 4): fitted systems beside their targets.

make(out) writes into out/inverse/:
  <target>.png        target | fit | overlay (white: both, red: target only, cyan: fit only)
  <target>.json       the fitted system (render it with `ifsforge render <target>.json`)
  fit_targets.md      IoU, Hausdorff distance, collage distance and time per target
The targets are those of cpp/bench/fit_targets.py (held-out classic attractors, skimage's horse).
Run alone: python3 samples/inverse/make_gallery.py [OUT]
"""
import importlib.util
import pathlib
import sys

import numpy as np

import ifsforge

HERE = pathlib.Path(__file__).resolve().parent
BENCH = HERE.parents[1] / "cpp" / "bench" / "fit_targets.py"


def bench():
    spec = importlib.util.spec_from_file_location("fit_targets", BENCH)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def panel(target, fit):
    """target | fit | overlay, white on black, with a gray gap."""
    t = target.astype(np.float32)
    f = fit.astype(np.float32)
    overlay = np.stack([np.maximum(t, 0) * 1.0, f, f], axis=2)  # target red, fit cyan, both white
    gap = np.full((t.shape[0], 4, 3), 0.3, np.float32)
    gray = lambda m: np.repeat(m[:, :, None], 3, axis=2)  # noqa: E731
    return np.concatenate([gray(t), gap, gray(f), gap, overlay], axis=1)


def make(out):
    out = pathlib.Path(out) / "inverse"
    out.mkdir(parents=True, exist_ok=True)
    module = bench()
    lines = ["| target | maps | IoU | Hausdorff (px) | collage (px) | time (s) |", "| --- | ---: | ---: | ---: | ---: | ---: |"]
    for name, target, maps in module.targets():
        r = module.evaluate(name, target, maps)
        stem = name.replace(" ", "_")
        ifsforge.write_png(str(out / f"{stem}.png"), panel(target, r["fit"]))
        r["system"].name = f"fit of {name}"
        ifsforge.write_json(str(out / f"{stem}.json"), r["system"])
        lines.append(f"| {name} | {maps} | {r['iou']:.3f} | {r['hausdorff_pixels']:.2f} | {r['collage_pixels']:.2f} | "
                     f"{r['seconds']:.1f} |")
        print(f"  {out / (stem + '.png')}: IoU {r['iou']:.3f}")
    (out / "fit_targets.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    make(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out"))
