#include "ifsforge/terrain/terrain_controls.h"

#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"

namespace ifsforge {

std::vector<std::vector<double>> random_heights(TerrainGrid grid, int rows, int columns,
                                                const std::vector<double>& base, double amplitude,
                                                std::uint64_t seed) {
  if (rows < 1 || columns < 1) throw InputError("random heights: need a positive number of rows and columns");
  if (base.size() != 1 && base.size() != std::size_t(rows))
    throw InputError("random heights: the base needs one value or one per row (" + std::to_string(rows) + "), got " +
                     std::to_string(base.size()));
  if (!std::isfinite(amplitude)) throw InputError("random heights: the amplitude is not finite");
  std::vector<std::vector<double>> out(rows, std::vector<double>(columns));
  for (int r = 0; r < rows; ++r) {
    const double b = base.size() == 1 ? base[0] : base[r];
    if (!std::isfinite(b)) throw InputError("random heights: base[" + std::to_string(r) + "] is not finite");
    Rng rng(seed, std::uint64_t(r));
    for (int c = 0; c < columns; ++c) out[r][c] = b + amplitude * (2.0 * rng.uniform() - 1.0);
    if (grid == TerrainGrid::Circular && r == 0) out[r].assign(columns, out[r][0]);  // the centre is one point
  }
  return out;
}

void random_shifts(TerrainControls& c, double amplitude, std::uint64_t seed) {
  if (!(std::fabs(amplitude) < 0.5)) throw InputError("random shifts: the amplitude must be below 0.5 (half a spacing)");
  if (c.grid == TerrainGrid::Regular) throw InputError("random shifts: a regular grid has no displacement");
  const std::size_t rows = c.heights.size(), columns = rows ? c.heights[0].size() : 0;
  c.shift_u.assign(rows, std::vector<double>(columns, 0.0));
  c.shift_v.assign(rows, std::vector<double>(columns, 0.0));
  Rng rng(seed, std::uint64_t(1) << 32);  // a stream of its own, apart from random_heights' rows
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t k = 0; k < columns; ++k) {
      const double du = amplitude * (2.0 * rng.uniform() - 1.0), dv = amplitude * (2.0 * rng.uniform() - 1.0);
      if (c.grid == TerrainGrid::Irregular) {
        if (k > 0 && k + 1 < columns) c.shift_u[r][k] = du;
        if (r > 0 && r + 1 < rows) c.shift_v[r][k] = dv;
      } else if (r > 0 && r + 1 < rows) {
        c.shift_u[r][k] = du;
        c.shift_v[r][k] = dv;
      }
    }
}

void sample_heights(TerrainControls& c, int rows, int columns, const Image& map, const std::array<double, 4>& window,
                    double low, double high) {
  if (map.width < 1 || map.height < 1 || map.channels < 1) throw InputError("sample heights: the height map is empty");
  for (double w : window)
    if (!(w >= 0.0 && w <= 1.0)) throw InputError("sample heights: the window must lie in [0, 1] (image coordinates)");
  if (!(window[2] > window[0] && window[3] > window[1]))
    throw InputError("sample heights: the window needs x0 < x1 and y0 < y1");
  if (rows < 2 || columns < 2) throw InputError("sample heights: need at least 2 x 2 control points");
  const bool circular = c.grid == TerrainGrid::Circular;
  if (circular && c.radii.size() != std::size_t(rows))
    throw InputError("sample heights: a circular grid needs its " + std::to_string(rows) + " radii first");
  auto shift = [&](const std::vector<std::vector<double>>& s, int r, int k) {
    return s.size() == std::size_t(rows) && s[r].size() == std::size_t(columns) ? s[r][k] : 0.0;
  };
  std::vector<float> channels(map.channels);
  c.heights.assign(rows, std::vector<double>(columns));
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < columns; ++k) {
      // The control point in the terrain's outline, as (X, Y) in [0, 1] with Y to the north.
      double x, y;
      if (circular) {
        const double p = r + shift(c.shift_v, r, k);
        const int lo = std::min(int(p), rows - 2);
        const double radius = c.radii[lo] + (c.radii[lo + 1] - c.radii[lo]) * (p - lo);
        const double angle = 2.0 * M_PI * (k + shift(c.shift_u, r, k)) / columns;
        const double scale = 0.5 / c.radii.back();
        x = 0.5 + scale * radius * std::cos(angle);
        y = 0.5 + scale * radius * std::sin(angle);
      } else {
        x = (k + shift(c.shift_u, r, k)) / double(columns - 1);
        y = (r + shift(c.shift_v, r, k)) / double(rows - 1);
      }
      // Vertex-centred, as the height images are: X = 0 is the centre of the first pixel.
      const double px = 0.5 + (window[0] + x * (window[2] - window[0])) * (map.width - 1);
      const double py = 0.5 + (window[3] - y * (window[3] - window[1])) * (map.height - 1);
      map.sample(px, py, channels.data());
      c.heights[r][k] = low + double(channels[0]) * (high - low);
    }
  if (circular) c.heights[0].assign(columns, c.heights[0][0]);
}

TerrainControls make_terrain_controls(const TerrainControlsOptions& options, std::uint64_t seed) {
  TerrainControlsOptions o = options;
  const bool circular = o.grid == TerrainGrid::Circular;
  if (o.rows == 0) o.rows = circular ? kDefaultCircles : kDefaultControls;
  if (o.columns == 0) o.columns = circular ? kDefaultCirclePoints : kDefaultControls;
  TerrainControls c;
  c.grid = o.grid;
  c.size_x = o.size_x;
  c.size_y = o.size_y;
  if (circular) {
    c.radii = o.radii;
    if (c.radii.empty())
      for (int k = 0; k < o.rows; ++k) c.radii.push_back(o.rows > 1 ? 0.5 * o.size_x * k / (o.rows - 1) : 0.0);
    if (c.radii.size() != std::size_t(o.rows))
      throw InputError("terrain controls: " + std::to_string(o.rows) + " leading circles need " +
                       std::to_string(o.rows) + " radii, got " + std::to_string(c.radii.size()));
  } else if (!o.radii.empty()) {
    throw InputError("terrain controls: radii belong to a circular grid");
  }
  if (o.height_map)
    sample_heights(c, o.rows, o.columns, *o.height_map, o.window, o.low, o.high);
  else
    c.heights = random_heights(o.grid, o.rows, o.columns, {o.base}, o.amplitude, seed);
  if (o.shift != 0.0) random_shifts(c, o.shift, seed);
  if (o.roughness) set_roughness(c, (*o.roughness)[0], (*o.roughness)[1], o.signs, seed);
  return c;
}

void set_roughness(TerrainControls& c, double along, double across, SignPattern signs, std::uint64_t seed) {
  if (c.heights.empty() || c.heights[0].empty()) throw InputError("roughness: the controls have no heights");
  const std::size_t rows = c.heights.size(), columns = c.heights[0].size();
  const std::size_t maps_u = c.grid == TerrainGrid::Circular ? columns : columns - 1;
  c.a22_u = vertical_scaling(maps_u, along, signs, seed, 1);
  c.a22_v = vertical_scaling(rows - 1, across, signs, seed, 2);
}

}  // namespace ifsforge
