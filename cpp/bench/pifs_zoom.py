#!/usr/bin/python3
"""Fractal zoom against bicubic upscaling (seed 3.3.2.2, resolution independence).

Each photo is reduced 2x or 4x (2x2 / 4x4 means) and compressed at raw bytes / R (R = 10, 20, 50).
The file is decoded at 2x or 4x, back to the original's size, and compared with the ORIGINAL
(PSNR over all channels, SSIM, and sharpness: gradient energy against the original's, 1 = as sharp)
three ways: the default decode (zoom=hybrid: the zoom filter of cpp/include/ifsforge/pifs/zoom.h),
the plain fractal decode (zoom=fractal), and the baseline, bicubic upscaling of the 1x decode.

The zoom filter's constants were chosen on the TRAINING photos only (--sweep emulates the filter
in numpy from the plain fractal decode and the 1x decode, for each share of fractal detail and
back-projection step); the HELD-OUT photos check them.

    PYTHONPATH=build/python cpp/bench/pifs_zoom.py [--threads 2] [--sweep]

Needs python3-skimage (photos, SSIM) and python3-pil. Prints Markdown tables.
"""
import argparse
import statistics
import sys
from pathlib import Path

import numpy as np
from PIL import Image
from skimage import data

sys.path.insert(0, str(Path(__file__).resolve().parent))
from pifs_vs_jpeg import IMAGES, psnr, ssim, to8  # noqa: E402
import ifsforge  # noqa: E402  (pifs_vs_jpeg put build/python on the path)

TRAINING = ("camera", "chelsea", "coins", "grass", "rocket", "rocket gray")
HELD_OUT = ("astronaut", "coffee", "moon", "gravel", "brick", "immunohistochemistry", "hubble deep field",
            "cell", "clock")
PHOTOS = {**IMAGES, "immunohistochemistry": data.immunohistochemistry, "hubble deep field": data.hubble_deep_field,
          "cell": data.cell, "clock": data.clock}
SCALES = (2, 4)
RATIOS = (10, 20, 50)


def gradient_energy(image):
    """Sharpness: mean squared difference of neighbouring pixels, across and down."""
    a = np.asarray(image, np.float64)
    return float(np.mean(np.diff(a, axis=0) ** 2) + np.mean(np.diff(a, axis=1) ** 2))


def bicubic(image, width, height):
    """Pillow's bicubic (Keys, a = -1/2) of an 8-bit or float image, per channel."""
    a = np.asarray(image, np.float32)
    if a.ndim == 3:
        return np.stack([bicubic(a[..., c], width, height) for c in range(a.shape[2])], axis=-1)
    return np.asarray(Image.fromarray(a, "F").resize((width, height), Image.BICUBIC))


def case(original, scale, ratio, threads):
    """The three upscales of one photo at one scale and ratio (8-bit, the original's size), and
    the 1x decode's PSNR with and without deblocking."""
    h, w = (s - s % scale for s in original.shape[:2])
    original = original[:h, :w]
    small = np.array(Image.fromarray(original).reduce(scale))
    code = ifsforge.pifs_encode(small, bytes=small.size // ratio, threads=threads)
    one = to8(code.decode(threads=threads))
    # The 1x decode against the reduced photo itself, with and without the deblocking filter.
    native = (psnr(small, one), psnr(small, to8(code.decode(deblock=False, threads=threads))))
    ups = {"hybrid": to8(code.decode(size=(w, h), threads=threads)),
           "fractal": to8(code.decode(size=(w, h), zoom="fractal", threads=threads)),
           "bicubic": np.round(np.clip(bicubic(one, w, h), 0, 255)).astype(np.uint8)}
    return original, code, ups, native


def strips(folder, threads, ratio=20):
    """zoom_<image>.png for the gallery: original | default 2x decode | bicubic of the 1x decode,
    a 160-pixel crop of each, from a file of the half-size photo, shown at 2x."""
    for name in ("camera", "coins", "astronaut"):
        original, _, ups, _ = case(PHOTOS[name](), 2, ratio, threads)
        h, w = original.shape[:2]
        crop = tuple(slice(s // 4, s // 4 + 160) for s in (h, w))
        strip = np.concatenate([original[crop], ups["hybrid"][crop], ups["bicubic"][crop]], axis=1)
        Image.fromarray(strip).resize((strip.shape[1] * 2, strip.shape[0] * 2), Image.NEAREST).save(
            Path(folder) / f"zoom_{name}.png")


def measure(threads):
    rows = []
    for name in TRAINING + HELD_OUT:
        photo = PHOTOS[name]()
        for scale in SCALES:
            for ratio in RATIOS:
                original, _, ups, native = case(photo, scale, ratio, threads)
                sharp = gradient_energy(original)
                row = {"image": name, "group": "training" if name in TRAINING else "held-out",
                       "scale": scale, "ratio": ratio, "native": native}
                for method, up in ups.items():
                    row[method] = (psnr(original, up), ssim(original, up), gradient_energy(up) / sharp)
                rows.append(row)
        print(f"  {name} done", file=sys.stderr)
    return rows


def sweep(threads, shares=(0, 0.1, 0.2, 0.3), steps=(0, 0.25, 0.5, 1)):
    """Gains over bicubic (dB) on the training photos for each filter setting, emulated per
    channel: a share of the fractal decode on the bicubic upscale, then one back-projection step."""
    gains = {}
    for name in TRAINING:
        photo = PHOTOS[name]()
        for scale in SCALES:
            for ratio in RATIOS:
                original, code, ups, _ = case(photo, scale, ratio, threads)
                h, w = original.shape[:2]
                native = code.decode(threads=threads) * 255.0
                fractal = code.decode(size=(w, h), zoom="fractal", threads=threads) * 255.0
                base = psnr(original, ups["bicubic"])
                up = bicubic(native, w, h)
                for share in shares:
                    x = (1 - share) * up + share * fractal
                    shape = (h // scale, scale, w // scale, scale) + x.shape[2:]
                    error = bicubic(native - x.reshape(shape).mean(axis=(1, 3)), w, h)
                    for step in steps:
                        gains.setdefault((scale, share, step), []).append(
                            psnr(original, np.clip(np.round(x + step * error), 0, 255)) - base)
    return gains


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--sweep", action="store_true", help="also the filter sweep on the training photos")
    import results
    results.add_argument(parser)
    args = parser.parse_args()
    with results.Section("pifs_zoom.py", args.results, "Fractal zoom against bicubic upscaling (pifs_zoom.py)") as out:
        report(args, out)


def cell(m):
    return f"{m[0]:.2f} / {m[1]:.3f}"


def report(args, out):
    if args.sweep:
        gains = sweep(args.threads)
        out.print("\nThe zoom filter on the training photos, emulated in numpy: photos improved over bicubic, "
                  "and the mean / worst gain in dB, for each share of fractal detail and back-projection step.\n")
        steps = sorted({k[2] for k in gains})
        out.print("| scale | fractal share | " + " | ".join(f"step {s}" for s in steps) + " |")
        out.print("|---|---|" + "---|" * len(steps))
        for scale in SCALES:
            for share in sorted({k[1] for k in gains}):
                g = [gains[(scale, share, s)] for s in steps]
                out.print(f"| {scale}x | {share} | " + " | ".join(
                    f"{sum(x > 0 for x in d)}/{len(d)}: {statistics.mean(d):+.2f} / {min(d):+.2f}" for d in g) + " |")
    rows = measure(args.threads)
    out.print("\nSummary: photos where the default decode (hybrid) beats bicubic upscaling of the 1x decode in "
              "PSNR, its mean and worst gain; the same for the plain fractal decode.\n")
    out.print("| group | scale | ratio | hybrid wins | mean | worst | fractal wins | mean | worst |")
    out.print("|---|---|---|---|---|---|---|---|---|")
    for group in ("training", "held-out"):
        for scale in SCALES:
            for ratio in RATIOS:
                sel = [r for r in rows if r["group"] == group and r["scale"] == scale and r["ratio"] == ratio]
                cells = []
                for method in ("hybrid", "fractal"):
                    d = [r[method][0] - r["bicubic"][0] for r in sel]
                    cells.append(f"{sum(x > 0 for x in d)}/{len(d)} | {statistics.mean(d):+.2f} dB | {min(d):+.2f} dB")
                out.print(f"| {group} | {scale}x | {ratio}:1 | " + " | ".join(cells) + " |")
    out.print("\nThe deblocking filter at 1x (the files above decoded at their own size, against the reduced "
              "photo): PSNR gain over no filter, mean and worst.\n")
    out.print("| group | 10:1 | 20:1 | 50:1 |")
    out.print("|---|---|---|---|")
    for group in ("training", "held-out"):
        cells = []
        for ratio in RATIOS:
            d = [r["native"][0] - r["native"][1] for r in rows if r["group"] == group and r["ratio"] == ratio]
            cells.append(f"{statistics.mean(d):+.2f} / {min(d):+.2f} dB")
        out.print(f"| {group} | " + " | ".join(cells) + " |")
    out.print("\nEvery case: PSNR (dB) / SSIM against the original, and sharpness (gradient energy / the "
              "original's) of hybrid, fractal and bicubic.\n")
    out.print("| image | group | scale | ratio | hybrid | fractal | bicubic | hybrid − bicubic | sharpness h / f / b |")
    out.print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        out.print(f"| {r['image']} | {r['group']} | {r['scale']}x | {r['ratio']}:1 | {cell(r['hybrid'])} | "
                  f"{cell(r['fractal'])} | {cell(r['bicubic'])} | {r['hybrid'][0] - r['bicubic'][0]:+.2f} dB | "
                  f"{r['hybrid'][2]:.2f} / {r['fractal'][2]:.2f} / {r['bicubic'][2]:.2f} |")


if __name__ == "__main__":
    main()
