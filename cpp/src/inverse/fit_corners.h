#pragma once
// What the fits (2D and 3D) share about a map's linear part: keeping it contractive, and the
// corner parametrisation of their last, local searches.
#include <array>
#include <cmath>
#include <vector>

#include "ifsforge/model/affine_map.h"

namespace ifsforge {

/// Shrinks the leading dim x dim block onto s = max_contraction when it exceeds it; returns the
/// excess (a penalty keeps the search inside the feasible set instead of piling up on its border).
inline double clamp_contraction(AffineMap& m, int dim, double max_contraction) {
  const double s = m.contraction_factor(dim);
  if (s <= max_contraction) return 0;
  const double k = max_contraction / s;
  for (int r = 0; r < dim; ++r)
    for (int c = 0; c < dim; ++c) m.a(r, c) *= k;
  return s - max_contraction;
}

/// Maps by where they send the origin and the unit points e_1..e_dim: a step of one cell in
/// any coordinate moves part of the copy by at most a cell (well scaled for a local search).
inline std::vector<double> to_corners(const std::vector<AffineMap>& maps, int dim) {
  std::vector<double> y;
  for (const AffineMap& m : maps)
    for (int c = 0; c <= dim; ++c)
      for (int r = 0; r < dim; ++r) y.push_back((c == 0 ? 0.0 : m.a(r, c - 1)) + m.b(r));
  return y;
}

inline std::vector<AffineMap> from_corners(const std::vector<double>& y, int dim, double max_contraction,
                                           double* excess) {
  std::vector<AffineMap> maps;
  double e = 0;
  const std::size_t per_map = std::size_t(dim) * (dim + 1);
  for (std::size_t i = 0; i + per_map <= y.size(); i += per_map) {
    AffineMap m(dim);
    for (int r = 0; r < dim; ++r) m.b(r) = y[i + r];
    for (int c = 0; c < dim; ++c)
      for (int r = 0; r < dim; ++r) m.a(r, c) = y[i + (c + 1) * dim + r] - y[i + r];
    e += clamp_contraction(m, dim, max_contraction);
    maps.push_back(m);
  }
  if (excess) *excess = e;
  return maps;
}

/// The corners (to_corners) moved onto the nearest points of the target's lattice, the grid of
/// cells of size `cell` through `origin`. A raster target is often made of copies whose corners
/// sit on its lattice (grid-aligned attractors); the IoU barely tells a corner a fraction of a cell
/// off from one on it, but the off one spreads the attractor over neighbouring cells of any
/// finer drawing, so the fits keep the snapped corners when the IoU does not drop.
inline std::vector<double> snap_corners(std::vector<double> y, int dim, const std::array<double, 3>& origin,
                                        double cell) {
  for (std::size_t c = 0; c < y.size(); ++c) y[c] = origin[c % dim] + std::round((y[c] - origin[c % dim]) / cell) * cell;
  return y;
}

/// IoU a snap of the corners to the target's lattice may cost (the chaos game's noise).
constexpr double kSnapTolerance = 0.005;

}  // namespace ifsforge
