#!/usr/bin/python3
"""The sample gallery: renders every system in samples/systems into OUT/ (default: out/),
plus a color-stealing picture and a contact sheet of everything, then runs every
samples/<area>/make_gallery.py (volumes, POV-Ray scenes, terrains, ...), whose make(out)
writes into out/<area>/. Run by samples/gallery.sh."""
import argparse
import importlib.util
import sys
import time
from pathlib import Path

import numpy as np

import ifsforge
from ifsforge.contact_sheet import contact_sheet

HERE = Path(__file__).resolve().parent
SIZE = 1024


def reference_picture(size=256):
    """A smooth colour field to steal colours from (the seed's 5.1.2 uses photographs)."""
    y, x = np.mgrid[0:size, 0:size] / (size - 1)
    return np.stack([0.5 + 0.5 * np.sin(6 * x), 0.4 + 0.6 * y * (1 - x), 0.5 + 0.5 * np.cos(5 * y * x)], axis=2)


def images(out):
    folder = out / "images"
    folder.mkdir(parents=True, exist_ok=True)
    made = []
    for path in sorted((HERE / "systems").glob("*.json")):
        system = ifsforge.read_json(str(path))
        defaults = system.render_defaults
        start = time.perf_counter()
        # A shaded 3D view needs the nearest surface per pixel, not a smooth density: PEPP 4.
        raster = ifsforge.render(system, defaults.get("algorithm", "chaos"), SIZE,
                                 window=defaults.get("window"), view=defaults.get("view"),
                                 points_per_pixel=4 if system.spatial_dims == 3 else 16)
        image = raster.to_image()
        ifsforge.write_png(str(folder / f"{path.stem}.png"), image)
        made.append(image)
        print(f"  {path.stem:24s} {time.perf_counter() - start:6.2f} s  {raster.points:>11,} points")
    fern = ifsforge.read_json(str(HERE / "systems" / "barnsley_fern.json"))
    picture = reference_picture()
    ifsforge.write_png(str(folder / "reference.png"), picture)
    stolen = ifsforge.render(fern, "color-stealing", SIZE, reference_image=picture).to_image("color")
    ifsforge.write_png(str(folder / "barnsley_fern_colour_stealing.png"), stolen)
    made.append(stolen)
    ifsforge.write_png(str(out / "gallery.png"), contact_sheet(made))
    print(f"  {len(made)} images and the contact sheet in {folder}")


def areas(out):
    """Each samples/<area>/make_gallery.py contributes its own part."""
    for script in sorted(HERE.glob("*/make_gallery.py")):
        spec = importlib.util.spec_from_file_location(f"gallery_{script.parent.name}", script)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        print(f"{script.parent.name}:")
        start = time.perf_counter()
        module.make(out)
        print(f"  {script.parent.name} done in {time.perf_counter() - start:.1f} s")


def main(argv):
    parser = argparse.ArgumentParser(description="Render the sample gallery (every system, then every "
                                     "samples/<area>/make_gallery.py).")
    parser.add_argument("out", nargs="?", default="out", help="output folder (default: out)")
    out = Path(parser.parse_args(argv[1:]).out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    print(f"ifsforge gallery -> {out}")
    print("images:")
    images(out)
    areas(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
