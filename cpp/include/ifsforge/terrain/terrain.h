#pragma once
/// @file 2.5D IFS terrains (seed 6.1.3.4): surfaces built from one-dimensional fractal
/// interpolations (Eq. 94) on regular, irregular and circular grids of control heights.
///
/// Every grid is a lattice of `rows` leading vectors with `columns` control points each:
/// - regular: row r runs along x at y = r / (rows - 1) of the extent, column c sits at
///   x = c / (columns - 1);
/// - irregular: the same lattice with each control point displaced horizontally;
/// - circular: row r is the leading circle of radius radii[r] (radii[0] = 0 is the centre),
///   column c sits at the angle 360° c / columns; the circle closes on itself.
/// The steps of the seed: (2) each leading vector is interpolated to the sample count along it;
/// (3, irregular and circular) its displacement is interpolated at the same samples; (4) each
/// vertical (radial) vector through the leading vectors is interpolated across them. All
/// factors a22 = 0 give the bilinear surface of the control heights.
#include <array>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"

namespace ifsforge {

enum class TerrainGrid { Regular, Irregular, Circular };
template <>
struct EnumNames<TerrainGrid> {
  static constexpr const char* what = "terrain grid";
  static constexpr NamedValue<TerrainGrid> values[] = {
      {TerrainGrid::Regular, "regular"},
      {TerrainGrid::Irregular, "irregular"},
      {TerrainGrid::Circular, "circular"}};
};

/// @brief Step 1: the control data of a terrain.
struct TerrainControls {
  TerrainGrid grid = TerrainGrid::Regular;
  /// rows x columns control heights: regular and irregular at least 5 x 5 (the seed's 25
  /// points); circular at least 3 circles (the centre included) of 4 points.
  std::vector<std::vector<double>> heights;
  /// Irregular and circular: horizontal displacement of each control point in units of the
  /// control spacing (|shift| < 0.5): shift_u along the leading vectors (x; the angle),
  /// shift_v across them (y; the radius). Empty: none. Boundary points keep the outline:
  /// irregular grids keep shift_u = 0 on the first and last column and shift_v = 0 on the
  /// first and last row; circular grids keep the centre and the outer circle in place.
  std::vector<std::vector<double>> shift_u, shift_v;
  /// Circular: the radius of each leading circle, increasing, radii[0] = 0.
  std::vector<double> radii;
  /// Roughness along the leading vectors: a22 of each of their maps (columns - 1 maps;
  /// circular: columns), or one value for all. Empty: 0.
  std::vector<double> a22_u;
  /// Roughness across them (the vertical or radial vectors): rows - 1 maps, or one value.
  std::vector<double> a22_v;
  /// Step 3: a22 for the displacement along the leading vectors (same count as a22_u, or one
  /// value). Empty: 0, the displacement varies linearly between control points.
  std::vector<double> a22_shift;
  /// Regular and irregular: the horizontal extent; the terrain is centred on the origin.
  double size_x = 1.0, size_y = 1.0;
};

/// @brief A sampled terrain: heights on a (rows x columns) lattice of parameters.
struct Terrain {
  TerrainGrid grid = TerrainGrid::Regular;
  int columns = 0;  ///< samples along the leading vectors (circular: angles, the last before 360°)
  int rows = 0;     ///< samples across them (circular: from the centre outwards)
  std::vector<float> heights;  ///< rows x columns, row-major
  /// Irregular and circular: the displaced lattice parameters of each sample (u: along the
  /// leading vectors in [0, 1], v: across them in [0, 1]); empty for regular grids.
  std::vector<float> u, v;
  double size_x = 1.0, size_y = 1.0;
  std::vector<double> radii;
  float min_height = 0.0f, max_height = 0.0f;

  float height(int row, int column) const { return heights[std::size_t(row) * columns + column]; }
  /// @brief World position (x, y, height) of a sample; x and y are centred on the origin.
  std::array<double, 3> position(int row, int column) const;
  /// @brief xmin, ymin, xmax, ymax of the terrain's outline.
  std::array<double, 4> extent() const;
};

/// @brief Interpolates the controls to `columns` x `rows` samples (circular: `columns` angles,
/// `rows` radii from the centre). Exact at every sample (the grid recursion of
/// grid_recursion.h), so a control height is reproduced exactly (in float) wherever a sample
/// falls on it: (columns - 1) a multiple of (control columns - 1) and (rows - 1) of
/// (control rows - 1); circular: columns a multiple of the control columns. InputError names
/// anything malformed, including displacements that fold the grid; MemoryBudgetError when the
/// samples do not fit. The result does not depend on `threads`.
Terrain make_terrain(const TerrainControls& controls, int columns, int rows, int threads = 0,
                     const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
