#pragma once
/// @file Palette recipes: a small JSON file ("format": "ifsforge-palette/1") naming the colour
/// space, the stops, the roughness of each component and the number of entries.
///
/// {"format": "ifsforge-palette/1", "name": "ochre lightness", "space": "hls",
///  "stops": [[30, 0.2, 0.6], [35, 0.5, 0.7], [28, 0.8, 0.5]],
///  "positions": [0, 0.4, 1],
///  "roughness": {"components": [0, 0.55, 0], "signs": "random", "seed": 3},
///  "entries": 256}
///
/// Each of the three components' roughness is a number (the magnitude of every a22, signs
/// from "signs" and "seed") or an array of one a22 per map. "positions", "roughness",
/// "entries" (256), "name" and "description" are optional.
#include <string>

#include "ifsforge/texture/palette.h"

namespace ifsforge {

struct PaletteRecipe {
  std::string name = "palette";
  std::string description;
  PaletteSpec spec;
  std::size_t entries = 256;
};

/// @brief Reads a recipe file; InputError names the file and the JSON path of any mistake.
PaletteRecipe read_palette_recipe(const std::string& path);
/// @brief The same from text; `source` names it in errors.
PaletteRecipe parse_palette_recipe(const std::string& text, const std::string& source = "palette recipe");

}  // namespace ifsforge
