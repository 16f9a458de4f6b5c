#pragma once
/// @file Terrain recipes: a small JSON file ("format": "ifsforge-terrain/1") holding the
/// control data of a terrain (6.1.3.4, step 1), its roughness, a resolution and a palette.
///
/// {
///   "format": "ifsforge-terrain/1",
///   "name": "ridge range", "description": "optional text",
///   "grid": "regular",                       // regular | irregular | circular
///   "heights": [[0.1, 0.3, ...], ...],       // rows x columns control heights, or
///              {"random": {"rows": 9, "columns": 9, "base": 0.5, "amplitude": 0.5, "seed": 1}}
///              // base: one number or one per row (a circle's profile from the centre out), or
///              {"map": "base.png", "rows": 9, "columns": 9, "window": [0, 0, 1, 1],
///               "low": 0, "high": 1}         // sampled from a height map (a terrain insert)
///   "radii": [0, 0.3, 0.6, 1],               // circular only: one per leading circle, from 0
///   "shift": {"u": [[...]], "v": [[...]]},   // irregular / circular displacements, or
///            {"random": {"amplitude": 0.3, "seed": 2}}
///   "roughness": {"u": 0.45, "v": [0.3, -0.2, 0.4, 0.1], "shift": 0.0,
///                 "signs": "random", "seed": 3},   // a number: |a22| of every map; an array: each a22
///   "size": [2.0, 1.0],                      // regular / irregular extent (default [1, 1])
///   "resolution": [1025, 1025],              // samples along and across the leading vectors
///   "palette": "earth.json"                  // a palette recipe file, or one inline
/// }
/// File names are relative to the recipe's folder. Only "format", "grid" and "heights" are
/// required.
#include <optional>
#include <string>

#include "ifsforge/terrain/terrain.h"
#include "ifsforge/io/palette_recipe.h"

namespace ifsforge {

struct TerrainRecipe {
  std::string name = "terrain";
  std::string description;
  TerrainControls controls;
  int columns = 0, rows = 0;  ///< the recipe's resolution; 0 when it has none
  std::optional<PaletteRecipe> palette;
};

/// @brief Reads a recipe file (and any height map or palette file it names); InputError names
/// the file and the JSON path of any mistake, including controls make_terrain would refuse.
TerrainRecipe read_terrain_recipe(const std::string& path);
/// @brief The same from text; files are looked up in `folder`; `source` names it in errors.
TerrainRecipe parse_terrain_recipe(const std::string& text, const std::string& source = "terrain recipe",
                                   const std::string& folder = ".");

}  // namespace ifsforge
