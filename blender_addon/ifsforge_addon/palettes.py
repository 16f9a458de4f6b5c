"""Fractal palettes (seed 6.1.3.3) for the palette and terrain generators: a recipe file, by
default the sample 'earth' (hypsometric tints)."""
import bpy

import ifsforge

from . import presets


def recipe_path(settings):
    """The palette recipe the settings name, as an absolute path (main thread: uses bpy)."""
    if settings["palette_recipe"]:
        return bpy.path.abspath(settings["palette_recipe"])
    return str(presets.sample("terrain", "earth.json"))


def make(path, entries):
    """(recipe, palette) of a recipe file with `entries` colors."""
    recipe = ifsforge.read_palette_recipe(path)
    return recipe, recipe.make(entries)
