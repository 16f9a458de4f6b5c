#pragma once
/// @file Where control heights come from (Step 1 of 6.1.3.4): the user, a seeded random
/// generator, or an existing height map (a terrain insert that follows its surroundings).
#include <array>
#include <cstdint>
#include <vector>

#include "ifsforge/core/image.h"
#include "ifsforge/terrain/terrain.h"

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

}  // namespace ifsforge
