"""A fractal palette (seed 6.1.3.3: colour stops joined component by component by fractal
interpolation, Eq. 94) as an image datablock: entries wide, `rows` high."""
import ifsforge

from . import palettes
from .generate_image import ImageGenerator
from .generators import register_generator


class PaletteGenerator(ImageGenerator):
    kind = 'PALETTE'
    label = "Palette"
    suffix = ".png"
    datablock = "image"

    needs = ("read_palette_recipe",)
    feature = "fractal palettes"

    def uses_system(self, settings):
        return False

    def draw(self, layout, settings, system):
        layout.prop(settings, "palette_recipe")
        layout.prop(settings, "palette_entries")
        layout.prop(settings, "palette_rows")

    def resolve(self, settings):
        settings["palette_recipe"] = palettes.recipe_path(settings)
        return settings

    def work(self, system, settings, path, progress):
        recipe, palette = palettes.make(settings["palette_recipe"], settings["palette_entries"])
        ifsforge.write_png(path, palette.to_image(settings["palette_rows"]), 16)
        return {"path": path, "summary": f"palette '{recipe.name}': {len(palette)} entries"}


register_generator(PaletteGenerator())
