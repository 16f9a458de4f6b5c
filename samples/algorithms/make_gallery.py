"""Gallery items of the rendering-algorithm catalogue (seed chapter 5) and the nD colour images
(seed 6.2.3.1, 6.4-6.5).

make(out) writes into out/algorithms/:
  compare_sierpinski/             `ifsforge compare` of the Sierpinski triangle at 512^2: every
                                  algorithm's image, contact_sheet.png, comparison.md/.json
  compare_fern.png                the same contact sheet for Barnsley's fern (afra does not apply)
  <colour sample>.png             each 2D + RGB / HSI / RGBA sample at 1024^2 (RGBA keeps alpha)
  colour5d_sierpinski_rgb_16bit.png   one of them as a 16-bit PNG
  colour_algorithms.png           the colour Sierpinski by every algorithm that carries channels
  superfractal_breed.png          six members of the superfractal pair (dia-s, seeds 0-5)
  recurrent_squares.png           the recurrent IFS by chaos, probabilistic-domain and photocopy
  condensation_tree_growth.png    the condensation tree growing, frame by frame (self-congruent)
  escape_time.png                 the escape time of every pixel (eta, output escape-time), fern
Run alone: python3 samples/algorithms/make_gallery.py [OUT]
"""
import pathlib
import sys
import time

import numpy as np

import ifsforge
from ifsforge.commands import compare
from ifsforge.contact_sheet import contact_sheet

HERE = pathlib.Path(__file__).resolve().parent
SYSTEMS = HERE.parent / "systems"
COLOUR = ["colour5d_sierpinski_rgb", "colour5d_fern_hsi", "colour5d_dragon_rgb", "rgba_carpet"]


def load(name):
    return ifsforge.read_json(str(SYSTEMS / f"{name}.json"))


def strip(images, gap=8):
    """Images side by side on a dark background (RGBA composited over it)."""
    rgb = []
    for image in images:
        if image.ndim == 2:
            image = np.repeat(image[:, :, None], 3, axis=2)
        if image.shape[2] == 4:
            image = image[:, :, :3] * image[:, :, 3:4]
        rgb.append(image[:, :, :3])
    height = max(i.shape[0] for i in rgb)
    out = np.full((height, sum(i.shape[1] for i in rgb) + gap * (len(rgb) - 1), 3), 0.05, np.float32)
    x = 0
    for image in rgb:
        out[:image.shape[0], x:x + image.shape[1]] = image
        x += image.shape[1] + gap
    return out


def render(system, algorithm, size, **kw):
    defaults = system.render_defaults
    return ifsforge.render(system, algorithm, size, window=defaults.get("window"), **kw)


def make(out):
    out = pathlib.Path(out) / "algorithms"
    out.mkdir(parents=True, exist_ok=True)

    # 1. Every algorithm on one system: the compare report.
    start = time.monotonic()
    sierpinski = load("sierpinski_triangle")
    folder = out / "compare_sierpinski"
    folder.mkdir(exist_ok=True)
    rows, images, reference = compare.compare(sierpinski, (512, 512), progress=False)
    for name, image in images.items():
        ifsforge.write_png(str(folder / f"{name}.png"), image)
    done = [r for r in rows if r["algorithm"] in images]
    ifsforge.write_png(str(folder / "contact_sheet.png"), contact_sheet(
        [images[r["algorithm"]] for r in done], [f"{r['algorithm']}\n{r['ms']:.0f} ms  iou {r['iou']:.3f}" for r in done]))
    (folder / "comparison.md").write_text(compare.markdown(sierpinski, rows, reference, (512, 512)))
    print(f"  {folder}: {len(images)} algorithms, contact_sheet.png, comparison.md  ({time.monotonic() - start:.1f} s)")

    start = time.monotonic()
    fern = load("barnsley_fern")
    rows, images, _ = compare.compare(fern, (512, 512), progress=False)
    done = [r for r in rows if r["algorithm"] in images]
    path = out / "compare_fern.png"
    ifsforge.write_png(str(path), contact_sheet(
        [images[r["algorithm"]] for r in done], [f"{r['algorithm']}\n{r['ms']:.0f} ms  iou {r['iou']:.3f}" for r in done]))
    print(f"  {path}: {len(done)} algorithms on the fern  ({time.monotonic() - start:.1f} s)")

    # 2. The nD colour samples (Eq. 97-105), normalised by Eq. 101.
    for name in COLOUR:
        start = time.monotonic()
        system = load(name)
        raster = render(system, system.render_defaults.get("algorithm", "chaos"), 1024)
        path = out / f"{name}.png"
        image = raster.to_image("color")
        ifsforge.write_png(str(path), image)
        print(f"  {path}: {system.layout}, {raster.covered():,} pixels  ({time.monotonic() - start:.1f} s)")
        if name == "colour5d_sierpinski_rgb":
            path = out / f"{name}_16bit.png"
            ifsforge.write_png(str(path), image, 16)
            print(f"  {path}: the same, 16 bits per channel")

    color = load("colour5d_sierpinski_rgb")
    algorithms = ["chaos", "dia", "mpa", "cma", "eta", "string-rewriting", "tsa", "prr", "ibr", "afra",
                  "self-congruent", "probabilistic-domain"]
    images = [render(color, a, 256).to_image("color") for a in algorithms]
    path = out / "colour_algorithms.png"
    ifsforge.write_png(str(path), contact_sheet(images, algorithms, columns=6))
    print(f"  {path}: the 2D + RGB Sierpinski by {len(algorithms)} algorithms")

    # 3. Model extensions.
    pair = load("superfractal_pair")
    path = out / "superfractal_breed.png"
    ifsforge.write_png(str(path), strip([render(pair, "dia-s", 384, seed=s).to_image("binary") for s in range(6)]))
    print(f"  {path}: six 2-variable members of the superfractal pair (seeds 0-5)")

    squares = load("recurrent_squares")
    path = out / "recurrent_squares.png"
    ifsforge.write_png(str(path), strip([render(squares, a, 384).to_image("binary")
                                         for a in ["chaos", "probabilistic-domain", "photocopy"]]))
    print(f"  {path}: chaos, probabilistic-domain and photocopy follow the transitions alike")

    tree = load("condensation_tree")
    frames = ifsforge.growth_frames(tree, 256, window=tree.render_defaults.get("window"))
    picks = sorted({round(k * (len(frames) - 1) / 5) for k in range(6)})
    path = out / "condensation_tree_growth.png"
    ifsforge.write_png(str(path), strip([frames[k].to_image("binary") for k in picks]))
    print(f"  {path}: growth frames {picks} of {len(frames)}")

    path = out / "escape_time.png"
    eta = render(fern, "eta", 768, parameters={"output": "escape-time"}).density
    # Covered pixels never escape (iterations + 1): show them white, the rest by escape time.
    escaped = eta < eta.max()
    image = np.where(escaped, np.sqrt(eta / (eta[escaped].max() + 1)) * 0.8, 1.0).astype(np.float32)
    ifsforge.write_png(str(path), image)
    print(f"  {path}: escape time of every pixel, fern")


if __name__ == "__main__":
    target = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out")
    make(target)
