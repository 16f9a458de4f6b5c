#pragma once
/// @file Where control heights come from (Step 1 of 6.1.3.4): the user, a seeded random
/// generator, or an existing height map (a terrain insert that follows its surroundings).
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "ifsforge/core/image.h"
#include "ifsforge/terrain/terrain.h"
#include "ifsforge/interpolation/vertical_scaling.h"

namespace ifsforge {

/// @brief rows x columns heights base[r] + amplitude (2 u - 1), u uniform in [0, 1) from
/// Rng(seed, r). `base` holds one value per row (a circular grid's profile from the centre
/// outwards) or one value for all. A circular grid's centre row gets a single height.
std::vector<std::vector<double>> random_heights(TerrainGrid grid, int rows, int columns,
                                                const std::vector<double>& base, double amplitude,
                                                std::uint64_t seed);

/// @brief Random displacements amplitude (2 u - 1), |amplitude| < 0.5, zero where the outline
/// must stay (see TerrainControls): fills controls.shift_u and shift_v.
void random_shifts(TerrainControls& controls, double amplitude, std::uint64_t seed);

/// @brief Samples the control heights of `controls` (its grid, its rows x columns, its radii
/// and displacements) from the first channel of `map`, bilinearly, at the control points'
/// positions. The terrain's outline maps onto `window` = (x0, y0, x1, y1) in [0, 1] image
/// coordinates (x to the right, y down; the terrain's north is up); values v in [0, 1] become
/// low + v (high - low). A circular grid's centre takes the map's value at the centre.
void sample_heights(TerrainControls& controls, int rows, int columns, const Image& map,
                    const std::array<double, 4>& window, double low = 0.0, double high = 1.0);

/// @brief The controls of a terrain described by settings rather than a recipe file: what the
/// CLI's `terrain` options and the add-on's panel fill in, so that one seed gives one terrain in
/// both (make_terrain_controls draws every random number).
/// The defaults of a terrain made without a recipe, the same in every front end (the command
/// line, the Blender add-on and Python read them from here).
constexpr int kDefaultControls = 9;        ///< regular and irregular grids: 9 x 9 control heights
constexpr int kDefaultCircles = 6;         ///< circular grids: 6 leading circles ...
constexpr int kDefaultCirclePoints = 12;   ///< ... of 12 control heights each
constexpr double kDefaultRoughness = 0.3;  ///< |a22| along and across: ridges, not a bilinear sheet
constexpr int kDefaultTerrainSamples = 257;  ///< samples per side (circular: the height image's side)

struct TerrainControlsOptions {
  TerrainGrid grid = TerrainGrid::Regular;
  /// The control lattice (circular: circles, points per circle); 0: the defaults above.
  int rows = 0, columns = 0;
  double base = 0.5, amplitude = 0.5;  ///< random heights: base + amplitude (2 u - 1)
  /// Sample the heights from this map (first channel) instead: its `window` in [0, 1] image
  /// coordinates, values v in [0, 1] as low + v (high - low) (see sample_heights).
  std::optional<Image> height_map;
  std::array<double, 4> window{0.0, 0.0, 1.0, 1.0};
  double low = 0.0, high = 1.0;
  /// Circular: the leading circles' radii; empty: `rows` radii evenly from 0 to size_x / 2.
  std::vector<double> radii;
  double shift = 0.0;  ///< irregular and circular: random displacement amplitude (0: none)
  /// |a22| along and across the leading vectors (none, or 0: a piecewise bilinear terrain).
  std::optional<std::array<double, 2>> roughness = std::array<double, 2>{kDefaultRoughness, kDefaultRoughness};
  SignPattern signs = SignPattern::Random;
  double size_x = 4.0, size_y = 4.0;  ///< the horizontal extent (heights around 0..1)
};

/// @brief The controls `options` describe, every random draw from `seed`: heights from
/// Rng(seed, row), displacements (random_shifts), then the a22 signs (set_roughness).
TerrainControls make_terrain_controls(const TerrainControlsOptions& options, std::uint64_t seed);

/// @brief Sets a22_u and a22_v to |along| and |across| with `signs`, the random signs from
/// Rng(seed, 1) along and Rng(seed, 2) across the leading vectors.
void set_roughness(TerrainControls& controls, double along, double across, SignPattern signs, std::uint64_t seed);

}  // namespace ifsforge
