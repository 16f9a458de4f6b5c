"""Gallery items of fractal interpolation, fractal palettes and IFS terrains (seed 6.1.3.2-6.1.3.4).

make(out) writes into out/terrain/:
  fractal_interpolation.png      one data set interpolated with growing vertical scaling (Eq. 94)
  palette_<name>.png             each sample palette as a 1024 x 48 texture
  <terrain>_height.png           16-bit height field of each sample terrain
  <terrain>_colour.png           the height field coloured by the terrain's palette
  <terrain>.pov                  the POV-Ray scene (a height_field reading <terrain>_height.png)
  <terrain>_povray.png           its POV-Ray render
Run alone: python3 samples/terrain/make_gallery.py [OUT]
"""
import pathlib
import sys
import time

import numpy as np

import ifsforge

HERE = pathlib.Path(__file__).resolve().parent
TERRAINS = ["ridge_range", "valley_insert", "crater", "volcano"]
PALETTES = ["earth", "ember_hls", "glacier_hsi"]


def interpolation_plot(path, width=1200, height=900):
    """Rows of graphs: the same 6 points with a22 = 0 (piecewise linear), 0.3, 0.55, 0.8."""
    x = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    values = [0.1, 0.9, 0.35, 0.75, 0.2, 0.6]
    image = np.ones((height, width, 3), np.float32)
    band = height // 4
    for row, d in enumerate([0.0, 0.3, 0.55, 0.8]):
        f = ifsforge.FractalInterpolation(x, values, [d, -d, d, -d, d])
        s = f.sample(width * 8 + 1)
        lo, hi = s.min(), s.max()
        pixel = band * row + 8 + ((hi - s) / (hi - lo) * (band - 16)).astype(int)
        color = np.array(ifsforge.hls_to_rgb(215 - 60 * row, 0.35, 0.8), np.float32)
        for column in range(width):
            a, b = pixel[column * 8:(column + 1) * 8 + 1].min(), pixel[column * 8:(column + 1) * 8 + 1].max()
            image[a:b + 1, column] = color
        for xi, fi in zip(x, values):  # the data points, exactly on every graph
            cx = int(round(xi / 5.0 * (width - 1)))
            cy = band * row + 8 + int(round((hi - fi) / (hi - lo) * (band - 16)))
            image[max(cy - 4, 0):cy + 5, max(cx - 4, 0):cx + 5] = (0.85, 0.1, 0.1)
        image[band * (row + 1) - 1, :] = 0.8
    ifsforge.write_png(str(path), image, 8)


def make(out):
    out = pathlib.Path(out) / "terrain"
    out.mkdir(parents=True, exist_ok=True)
    start = time.monotonic()

    path = out / "fractal_interpolation.png"
    interpolation_plot(path)
    print(f"{path}: 6 data points, a22 = 0, 0.3, 0.55, 0.8 (top to bottom)")

    for name in PALETTES:
        recipe = ifsforge.read_palette_recipe(str(HERE / f"{name}.json"))
        path = out / f"palette_{name}.png"
        ifsforge.write_png(str(path), recipe.make(1024).to_image(48), 8)
        print(f"{path}: {recipe.name} ({recipe.spec.space}) fractal palette")

    for name in TERRAINS:
        recipe = ifsforge.read_terrain_recipe(str(HERE / f"{name}.json"))
        terrain = ifsforge.make_terrain(recipe.controls, recipe.columns, recipe.rows)
        palette = recipe.palette.make()
        height = terrain.height_image()
        path = out / f"{name}_height.png"
        ifsforge.write_png(str(path), height, 16)
        print(f"{path}: {recipe.name}, {terrain.grid} grid, 16-bit {height.shape[1]}x{height.shape[0]}")
        path = out / f"{name}_colour.png"
        ifsforge.write_png(str(path), ifsforge.apply_palette(height, palette), 8)
        print(f"{path}: {recipe.name} coloured by the '{recipe.palette.name}' palette")
        scene = out / f"{name}.pov"
        ifsforge.write_terrain_pov(str(scene), terrain, palette, aspect=4 / 3)
        path = out / f"{name}_povray.png"
        ifsforge.render_povray(str(scene), str(path), 800, 600)
        print(f"{path}: POV-Ray 3.7 render of {scene.name} (height_field + color_map)")
    print(f"terrain gallery: {time.monotonic() - start:.1f} s")


if __name__ == "__main__":
    make(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out"))
