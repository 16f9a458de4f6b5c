"""The polar part of the gallery (seed 3.3.3): the sample polar system by chaos and by prr side by
side, and a sheet of bred phenotypes (`ifsforge breed`)."""
import time
from pathlib import Path

import ifsforge
from ifsforge.commands.breed import tinted
from ifsforge.contact_sheet import contact_sheet

HERE = Path(__file__).resolve().parent
SIZE = 512
BREED_SEED = 7


def make(out):
    folder = out / "polar"
    folder.mkdir(parents=True, exist_ok=True)
    system = ifsforge.read_json(str(HERE.parent / "systems" / "polar_spirals.json"))
    images, labels = [], []
    for algorithm in ("chaos", "prr"):
        start = time.perf_counter()
        raster = ifsforge.render(system, algorithm, SIZE)
        seconds = time.perf_counter() - start
        images.append(tinted(raster, 0))
        labels.append(f"{algorithm}  {seconds:.2f} s")
        ifsforge.write_png(str(folder / f"polar_spirals_{algorithm}.png"), images[-1])
        print(f"  polar_spirals {algorithm:6s} {seconds:6.2f} s  {raster.points:>11,} points")
    ifsforge.write_png(str(folder / "polar_spirals.png"), contact_sheet(images, labels, columns=2, cell=SIZE))
    start = time.perf_counter()
    phenotypes = ifsforge.breed(count=16, seed=BREED_SEED)
    cells = [tinted(ifsforge.render(s, "chaos", 256), k) for k, s in enumerate(phenotypes)]
    ifsforge.write_png(str(folder / "breed.png"), contact_sheet(cells, columns=4, cell=256))
    print(f"  breed seed {BREED_SEED}: 16 phenotypes in {time.perf_counter() - start:.1f} s")
