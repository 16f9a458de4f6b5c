#pragma once
// The triangulation shared by the terrain mesh and the height-image rasteriser.
#include <array>
#include <cstddef>

#include "ifsforge/terrain/terrain.h"

namespace ifsforge::detail {

/// Cells per lattice row: a circle closes on itself, other grids stop at the last column.
inline std::size_t cells_across(const Terrain& t) {
  return t.grid == TerrainGrid::Circular ? std::size_t(t.columns) : std::size_t(t.columns) - 1;
}

/// The two triangles of cell (row, column) as lattice sample indices, counter-clockwise seen
/// from above. Lattice orientation: u runs east (or counter-clockwise round a circle), v runs
/// north (or outwards), so a cell's u-v order is counter-clockwise on rectangular grids and
/// clockwise on circular ones.
inline std::array<std::array<std::size_t, 3>, 2> cell_triangles(const Terrain& t, std::size_t row, std::size_t column) {
  const std::size_t w = t.columns, next = (column + 1) % w;
  const std::size_t a = row * w + column, b = row * w + next, c = (row + 1) * w + next, d = (row + 1) * w + column;
  if (t.grid == TerrainGrid::Circular) return {{{a, c, b}, {a, d, c}}};
  return {{{a, b, c}, {a, c, d}}};
}

}  // namespace ifsforge::detail
