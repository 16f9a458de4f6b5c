"""Gallery items of the inverse problem (seed chapter 4): fitted systems beside their targets.

make(out) writes into out/inverse/:
  <target>.png        target | fit | overlay (white: both, red: target only, cyan: fit only)
  <target>.json       the fitted system (render it with `ifsforge render <target>.json`)
  colour_<target>.png target | fit | 4 x |difference| (colour pictures, one collage per channel)
  shape_<target>.png  target | fit | overlay of the voxels projected along z, then along x
  fit_targets.md      IoU, Hausdorff distance, collage distance and time per target; colour error;
                      3D IoU
The targets are those of cpp/bench/fit_targets.py (held-out classic attractors, skimage's horse,
the colour samples, 3D samples as .vdb and mesh).
Run alone: python3 samples/inverse/make_gallery.py [OUT]
"""
import importlib.util
import pathlib
import sys
import tempfile

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


def colour_panel(target, fit):
    """target | fit | 4 x |difference|, colour, with a gray gap."""
    gap = np.full((target.shape[0], 4, 3), 0.3, np.float32)
    return np.concatenate([target, gap, fit, gap, np.clip(4 * np.abs(target - fit), 0, 1)], axis=1)


def shape_panel(target, fit):
    """The voxels projected along z (rows: y, top up) and along x (rows: z), as target | fit | overlay."""
    def view(mask, axis):  # 3 x 3 screen pixels per voxel: a 64^3 target is small
        return np.kron(mask.any(axis=axis).T[::-1], np.ones((3, 3), bool))
    rows = [panel(view(target, axis), view(fit, axis)) for axis in (2, 0)]
    width = max(r.shape[1] for r in rows)
    rows = [np.pad(r, ((0, 0), (0, width - r.shape[1]), (0, 0)), constant_values=0.3) for r in rows]
    return np.concatenate([rows[0], np.full((4, width, 3), 0.3, np.float32), rows[1]], axis=0)


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
    lines += ["", "| colour target | maps | IoU | colour error per pixel | collage RMS r, g, b | time (s) |",
              "| --- | ---: | ---: | ---: | ---: | ---: |"]
    for name, picture, maps in module.color_targets():
        r = module.evaluate_color(name, picture, maps)
        stem = "colour_" + name.replace(" ", "_")
        ifsforge.write_png(str(out / f"{stem}.png"), colour_panel(picture, r["fit"]))
        r["system"].name = f"fit of {name}"
        ifsforge.write_json(str(out / f"{stem}.json"), r["system"])
        lines.append(f"| {name} | {maps} | {r['iou']:.3f} | {r['color_error']:.4f} | "
                     f"{', '.join(f'{e:.3f}' for e in r['collage_error'])} | {r['seconds']:.1f} |")
        print(f"  {out / (stem + '.png')}: colour error {r['color_error']:.4f}")
    lines += ["", "| 3D target | maps | voxels | IoU | time (s) |", "| --- | ---: | --- | ---: | ---: |"]
    with tempfile.TemporaryDirectory() as folder:
        for name, (file, maps, extension) in module.SHAPES.items():
            target = module.shape_target(file, extension, folder)
            r = module.evaluate_3d(name, target, maps)
            stem = "shape_" + name.split(" (")[0].replace(" ", "_") + "_" + extension[1:]
            ifsforge.write_png(str(out / f"{stem}.png"), shape_panel(target["mask"], r["fit"]))
            r["system"].name = f"fit of {name}"
            ifsforge.write_json(str(out / f"{stem}.json"), r["system"])
            lines.append(f"| {name} | {maps} | {'x'.join(map(str, r['voxels']))} | {r['iou']:.3f} | {r['seconds']:.1f} |")
            print(f"  {out / (stem + '.png')}: IoU {r['iou']:.3f}")
    (out / "fit_targets.md").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    make(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out"))
