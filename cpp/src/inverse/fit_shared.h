#pragma once
// What the fits (2D and 3D) share: their CMA-ES settings and time limit, keeping a map's linear
// part contractive, the corner parametrisation of their last, local searches and the snap of the
// corners to the target's lattice, and the attractor's IoU from the cells a chaos game hit.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/inverse/cma_es.h"
#include "ifsforge/model/affine_map.h"
#include "ifsforge/model/map_params.h"

namespace ifsforge {

/// The searches' CMA-ES: twice the default population (the fitness is rugged), seeded.
inline CmaOptions fit_cma_options(int n, int generations, std::uint64_t seed, int threads) {
  CmaOptions co;
  co.population = 2 * (4 + static_cast<int>(3 * std::log(double(n))));
  co.max_generations = generations;
  co.seed = seed;
  co.threads = threads;
  co.floor = 0;  // every fit's value (a collage distance, 1 - IoU, plus penalties) is >= 0
  return co;
}

/// One restart of a fit: CMA-ES from x0 on the collage proxy, then a short run on the attractor
/// itself with a quarter of the steps (the collage's optimum is near, not at, the attractor's:
/// Eq. 42 only bounds the gap); the restarts compete on the attractor's value, returned.
template <typename Collage, typename Attractor, typename Stop>
CmaResult collage_then_attractor(const Collage& collage, const Attractor& attractor, const std::vector<double>& x0,
                                 std::vector<double> sigma, CmaOptions co, int attractor_generations, const Stop& stop) {
  const CmaResult run = minimize_cma(collage, x0, sigma, co, stop);
  for (double& v : sigma) v *= 0.25;
  co.max_generations = attractor_generations;
  CmaResult polish = minimize_cma(attractor, run.best, sigma, co, stop);
  polish.evaluations += run.evaluations;
  return polish;
}

/// A fit's start (FitOptions::start, Fit3dOptions::start): none, or `maps` maps of `dim` dimensions.
inline void check_start(const std::vector<AffineMap>& start, int maps, int dim) {
  if (start.empty()) return;
  if (int(start.size()) != maps)
    throw InputError("the start has " + std::to_string(start.size()) + " maps, the fit asks " + std::to_string(maps));
  for (const AffineMap& m : start)
    if (m.dim() != dim) throw InputError("the start's maps must have " + std::to_string(dim) + " dimensions");
}

/// The collage proxy's weight of the copies' overlap: a negative one would reward overlap, and
/// every fit's value must stay >= 0 (fit_cma_options' floor).
inline void check_overlap_weight(double weight) {
  if (!(weight >= 0 && weight <= 1e6))
    throw InputError("the overlap weight must lie in [0, 1e6], got " + std::to_string(weight));
}

/// The time limit of a fit (0: none): stop() turns true, and stays so, once it has passed.
class FitDeadline {
 public:
  explicit FitDeadline(double seconds) : seconds_(seconds), start_(std::chrono::steady_clock::now()) {}
  bool stop() {
    if (seconds_ > 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count() > seconds_)
      passed_ = true;
    return passed_;
  }
  bool passed() const { return passed_; }

 private:
  double seconds_;
  std::chrono::steady_clock::time_point start_;
  bool passed_ = false;
};

/// Intersection over union of the cells a chaos game hit with the target's; `out` of its
/// `points` left the grid and stand for as many cells as their share of the points.
inline double hits_iou(const std::vector<std::uint8_t>& hits, const std::vector<std::uint8_t>& target,
                       std::uint64_t points, std::uint64_t out) {
  std::size_t inter = 0, uni = 0, covered = 0;
  for (std::size_t c = 0; c < hits.size(); ++c) {
    inter += hits[c] && target[c];
    uni += hits[c] || target[c];
    covered += hits[c];
  }
  const double lost = covered * (double(out) / std::max<std::uint64_t>(points - out, 1));
  return uni ? inter / (uni + lost) : 0.0;
}

/// Fitness added per unit of contraction beyond the limit (clamp_contraction's excess).
constexpr double kExcessPenalty = 10.0;

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

/// Eq. 5 (2D) and its 3D analogue (map_params.h) from `dim` signed scales (a negative one is
/// the reflection F), `dim` angles (radians: 2D theta_x, theta_y; 3D about x, y, z) and `dim`
/// translations, shrunk onto max_contraction (clamp_contraction, whose excess it returns).
inline double decode_map(const double* p, int dim, double max_contraction, AffineMap& out) {
  MapParams mp;
  mp.dim = dim;
  for (int a = 0; a < dim; ++a) {
    mp.scale[a] = std::abs(p[a]);
    mp.reflect[a] = p[a] < 0;
    mp.rotation[a] = p[dim + a] * 180 / M_PI;
    mp.translation[a] = p[2 * dim + a];
  }
  out = map_from_params(mp);
  return clamp_contraction(out, dim, max_contraction);
}

/// Every map of a search point (3 dim parameters per map, decode_map); the summed excess in `excess`.
inline std::vector<AffineMap> decode_maps(const std::vector<double>& x, int dim, double max_contraction,
                                          double* excess) {
  const std::size_t per_map = 3 * std::size_t(dim);
  std::vector<AffineMap> maps(x.size() / per_map);
  double e = 0;
  for (std::size_t i = 0; i < maps.size(); ++i) e += decode_map(&x[i * per_map], dim, max_contraction, maps[i]);
  if (excess) *excess = e;
  return maps;
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
