"""Gallery items of fractal image compression (seed 3.3.2).

make(out) writes into out/pifs/:
  rate_distortion.png     PSNR against compression ratio: PIFS, JPEG, JPEG 2000 (equal bytes)
  zoom_<image>.png        original | PIFS decoded 2x | bicubic of its 1x decode, from the half-size image
  chelsea_50to1.pifs      a 50:1 code, and chelsea_closeup_4x.png: a crop of it decoded at 4x
Run alone: python3 samples/pifs/make_gallery.py [OUT]   (needs python3-skimage, -pil, -matplotlib)
"""
import importlib.util
import pathlib
import sys

import numpy as np

import ifsforge

ROOT = pathlib.Path(__file__).resolve().parents[2]


def bench(name="pifs_vs_jpeg"):
    spec = importlib.util.spec_from_file_location(name, ROOT / "cpp" / "bench" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def make(out):
    folder = pathlib.Path(out) / "pifs"
    folder.mkdir(parents=True, exist_ok=True)
    b = bench()
    images = {name: f() for name, f in b.IMAGES.items()}
    b.plot(b.rate_distortion(images, 0), folder / "rate_distortion.png")
    bench("pifs_zoom").strips(folder, 0)
    chelsea = images["chelsea"]
    code = ifsforge.pifs_encode(chelsea, ratio=50)
    ifsforge.write_pifs(str(folder / "chelsea_50to1.pifs"), code)
    big = code.decode(scale=4)
    h, w = big.shape[:2]
    ifsforge.write_png(str(folder / "chelsea_closeup_4x.png"), np.ascontiguousarray(big[h // 3:h // 3 + 512, w // 3:w // 3 + 512]))
    print(f"  rate-distortion plot, zoom strips and a 4x close-up in {folder}")


if __name__ == "__main__":
    make(sys.argv[1] if len(sys.argv) > 1 else "out")
