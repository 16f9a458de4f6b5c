#pragma once
/// @file The occupancy rule shared by pixels and voxels: a cell is occupied when the
/// attractor's measure in its interior is positive. A piece whose box lies on cell boundaries
/// (a grid-aligned fractal) occupies the cells its box covers, never the neighbours it only
/// touches; coordinates are continuous cell coordinates (cell i covers [i, i + 1)).
#include <cmath>
#include <cstdint>

namespace ifsforge {

/// Box sides within this many cells of a cell boundary lie on it: floating point places the
/// pieces of a grid-aligned fractal (1/3 of 81 cells) on boundaries only up to rounding.
constexpr double kCellTolerance = 1e-6;

/// @brief The cells [first, last] along one axis whose interior the box side [lo, hi] meets,
/// up to kCellTolerance. A side shorter than that (a flat piece) gives the cell of its centre.
inline void covered_cells(double lo, double hi, std::int64_t& first, std::int64_t& last) {
  first = static_cast<std::int64_t>(std::floor(lo + kCellTolerance));
  last = static_cast<std::int64_t>(std::ceil(hi - kCellTolerance)) - 1;
  if (last < first) first = last = static_cast<std::int64_t>(std::floor(0.5 * (lo + hi)));
}

/// @brief True when the box [lo, hi] (the first `axes` axes) has measure in the interior of
/// one cell only (covered_cells gives one cell per axis).
inline bool in_one_cell(const double* lo, const double* hi, int axes) {
  for (int a = 0; a < axes; ++a) {
    std::int64_t first, last;
    covered_cells(lo[a], hi[a], first, last);
    if (first != last) return false;
  }
  return true;
}

/// @brief True when the continuous cell coordinate `u` lies on a cell boundary, up to
/// kCellTolerance: a point there may belong to either neighbour.
/// (floor, not round: it compiles to one instruction, round to a call.)
inline bool on_cell_edge(double u) { return std::abs(u - std::floor(u + 0.5)) <= kCellTolerance; }

}  // namespace ifsforge
