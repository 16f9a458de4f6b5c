#include "ifsforge/inverse/fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/inverse/cma_es.h"
#include "ifsforge/inverse/collage.h"
#include "fit_clusters.h"
#include "fit_moments.h"
#include "fit_seed.h"
#include "fit_shared.h"
#include "fit_raster.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {
namespace {

constexpr int kParams = 6;   // per map: Mx, My, theta_x, theta_y (radians), tx, ty (Eq. 5, decode_map)
constexpr int kTurns = 36;  // turns tried per map for the rotated starts
// The cover's beam (fit_seed.h) costs several greedy covers: the first cover start runs it only
// when the k-means starts, run first, leave the attractor's IoU on the search's grid below
// kBeamBelow (the Sierpinski triangle's and the four-corner dust's reach it), the second only
// when the best start so far is below kBeamAgainBelow (a near exact start needs no other).
constexpr double kBeamBelow = 0.85;
constexpr double kBeamAgainBelow = 0.95;
// One more run, from the affine start (ellipse_collage), after the restarts when they leave the
// attractor's IoU on the search's grid below kAffineBelow (the held-out rotated systems' reach
// it; a drawn letter's do not) in a fit that ends with the last search (--maps auto's probes,
// which rank counts, skip it), and only once every kind of start has run (a fit asked for fewer
// restarts is a short one). Its steps: a fifth of a turn, a twentieth of the scales.
constexpr double kAffineBelow = 0.9;
constexpr int kStartKinds = 4;  // the restarts' kinds of start, taken in turn
constexpr double kAffineSigma[3] = {0.05, 0.15, 0.04};  // scales, turns (radians), translations (extents)

using Boxes = Clusters<2>;

/// The centres of the target's cells, in the plane.
std::vector<std::array<double, 2>> target_points(const PixelSet& t, const FitGrid& grid) {
  std::vector<std::array<double, 2>> pts;
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x)
      if (t.cells[std::size_t(y) * t.width + x]) pts.push_back(grid.to_plane(x + 0.5, y + 0.5));
  return pts;
}

/// k-means of the target's pixels into n clusters (fit_clusters.h), in the plane.
Boxes pixel_clusters(const PixelSet& t, const FitGrid& grid, int n, Rng& rng) {
  return cluster_boxes<2>(target_points(t, grid), n, 1.0 / grid.pixels_per_unit, rng);
}

/// The initial collage: map c sends the whole target's box onto part c's box.
std::vector<double> initial_collage(const Boxes& boxes) {
  const auto& whole = boxes.whole;
  const double wx = whole[2] - whole[0], wy = whole[3] - whole[1];
  std::vector<double> x;
  for (const auto& b : boxes.parts) {
    const double sx = std::clamp((b[2] - b[0]) / wx, 0.05, 0.85), sy = std::clamp((b[3] - b[1]) / wy, 0.05, 0.85);
    // b = centre(C) - S centre(B)
    for (double v : {sx, sy, 0.0, 0.0, 0.5 * (b[0] + b[2] - (whole[0] + whole[2]) * sx),
                     0.5 * (b[1] + b[3] - (whole[1] + whole[3]) * sy)})
      x.push_back(v);
  }
  return x;
}

/// Each map scaled by its part's share of the area, centroid onto centroid, turned (kTurns
/// angles, from a seeded offset) and mirrored to keep its copy nearest the target: a map at a
/// time, since one copy's distance to the target is its own share of Eq. 41's.
void turn_parts(const Boxes& boxes, const PixelSet& target, const FitGrid& grid, const CollageProxy& proxy,
                const FitOptions& o, Rng& rng, std::vector<double>& x0, std::uint64_t& evaluations) {
  const double turn = rng.uniform();
  for (int c = 0; c < o.maps; ++c) {
    const auto& mc = boxes.mass[c];
    const double sc = std::clamp(std::sqrt(mc[2] / target.count()), 0.05, o.max_contraction);
    double best_score = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 2 * kTurns; ++k) {
      double p[kParams] = {k % 2 ? -sc : sc, sc, 0, 0, 0, 0};
      p[2] = p[3] = (k / 2 + turn) * 2 * M_PI / kTurns;
      AffineMap m;
      decode_map(p, 2, o.max_contraction, m);
      p[4] = mc[0] - (m.a(0, 0) * boxes.centroid[0] + m.a(0, 1) * boxes.centroid[1]);
      p[5] = mc[1] - (m.a(1, 0) * boxes.centroid[0] + m.a(1, 1) * boxes.centroid[1]);
      decode_map(p, 2, o.max_contraction, m);
      const double score = proxy.copy_outside(grid.pixel_map(m));
      if (score < best_score) best_score = score, std::copy(p, p + kParams, &x0[std::size_t(c) * kParams]);
    }
  }
  evaluations += 2 * kTurns * o.maps;
}

/// The affine start: map c carries the whole target's centroid and covariance ellipse onto k-means
/// part c's (ellipse_map), turned and mirrored (2 kTurns ways, from a seeded offset) to keep its
/// copy nearest the target. A filled shape's parts are thin pieces of its strokes, covered by the
/// whole squashed into them; a part of fewer than three cells keeps initial_collage's box map.
std::vector<double> ellipse_collage(const PixelSet& target, const FitGrid& grid, const CollageProxy& proxy,
                                    const FitOptions& o, Rng& rng, std::uint64_t& evaluations) {
  const auto pts = target_points(target, grid);
  const Boxes boxes = cluster_boxes<2>(pts, o.maps, 1.0 / grid.pixels_per_unit, rng);
  const auto parts = cluster_parts<2>(pts, boxes);
  const Moments whole = moments_of(pts);
  std::vector<double> x0 = initial_collage(boxes);
  const double turn = rng.uniform();
  for (int c = 0; c < o.maps; ++c) {
    if (parts[c].size() < 3) continue;
    const Moments piece = moments_of(parts[c]);
    double best_score = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 2 * kTurns; ++k) {
      const auto p = ellipse_map(whole, piece, (k / 2 + turn) * 2 * M_PI / kTurns, k % 2);
      AffineMap m;
      decode_map(p.data(), 2, o.max_contraction, m);
      const double score = proxy.copy_outside(grid.pixel_map(m));
      if (score < best_score) best_score = score, std::copy(p.begin(), p.end(), &x0[std::size_t(c) * kParams]);
    }
  }
  evaluations += 2 * kTurns * o.maps;
  return x0;
}

}  // namespace

FitResult fit_ifs(const PixelSet& full, const FitOptions& o) {
  if (o.maps < 1 || o.maps > 64) throw InputError("--maps must be 1..64, got " + std::to_string(o.maps));
  if (o.restarts < 1) throw InputError("restarts: at least one CMA-ES run, got " + std::to_string(o.restarts));
  if (o.raster < 8 || o.raster > 1024) throw InputError("the fit raster must be 8..1024 cells, got " + std::to_string(o.raster));
  if (!(o.max_contraction > 0 && o.max_contraction < 1))
    throw InputError("the largest contraction must lie in (0, 1), got " + std::to_string(o.max_contraction));
  check_overlap_weight(o.overlap_weight);
  if (full.count() == 0) throw InputError("the target has no pixels");
  check_start(o.start, o.maps, 2);
  FitDeadline deadline(o.time_limit);
  const FitGrid grid = FitGrid::for_target(full, o.raster);
  const PixelSet target = grid.downsample(full);
  const int threads = resolve_threads(o.threads);
  std::vector<CollageProxy::Scratch> scratch(threads);
  const CollageProxy proxy(target, o.overlap_weight);
  auto to_pixels = [&](const std::vector<AffineMap>& maps) {
    std::vector<PixelMap> out;
    for (const AffineMap& m : maps) out.push_back(grid.pixel_map(m));
    return out;
  };
  auto collage_value = [&](const std::vector<double>& x, int worker) {
    double excess = 0;
    const auto maps = decode_maps(x, 2, o.max_contraction, &excess);
    return proxy(to_pixels(maps), scratch[worker]) + kExcessPenalty * excess;
  };
  // The attractor's overlap with the target on a grid (the search's, or the finer one of the
  // refinement, where one cell of the search's grid would hide misplaced detail).
  auto attractor_on = [&](const FitGrid& g, const PixelSet& t) {
    return [&, g, t](const std::vector<double>& x, int worker) {
      double excess = 0;
      const auto maps = decode_maps(x, 2, o.max_contraction, &excess);
      std::vector<PixelMap> pm;
      for (const AffineMap& m : maps) pm.push_back(g.pixel_map(m));
      return 1.0 - chaos_iou(pm, jacobian_probabilities(maps, 2), t, o.seed, scratch[worker]) + kExcessPenalty * excess;
    };
  };
  const auto attractor_value = attractor_on(grid, target);
  auto stop = [&] { return deadline.stop(); };
  FitResult result;
  std::vector<double> best;
  double best_value = std::numeric_limits<double>::infinity();
  const int n = o.maps * kParams;
  for (int r = 0; r < o.restarts && o.start.empty() && !stop(); ++r) {
    Rng rng(o.seed, 1000 + r);
    // Four kinds of start, in turn: the k-means collage as it is, the k-means parts turned one
    // at a time, and the target covered by turned copies of itself (its own structure), judged on
    // the search's grid and on the refinement's (fit_seed.h).
    const int kind = r % kStartKinds;
    std::vector<double> x0;
    if (kind >= 2) {
      x0 = self_similar_cover(full, target, grid, o.maps, kind == 2 ? o.raster : o.refine_raster, o.max_contraction,
                              best_value > 1 - (kind == 2 ? kBeamBelow : kBeamAgainBelow), threads, rng,
                              result.evaluations, stop);
    } else {
      const Boxes boxes = pixel_clusters(target, grid, o.maps, rng);
      x0 = initial_collage(boxes);
      if (kind == 1) turn_parts(boxes, target, grid, proxy, o, rng, x0, result.evaluations);
    }
    std::vector<double> sigma(n);
    for (int i = 0; i < n; ++i) {
      const int k = i % kParams;
      sigma[i] = k < 2 ? 0.1 : k < 4 ? (kind == 1 ? 0.6 : 0.3) : 0.08 * grid.extent;
    }
    const CmaResult polish = collage_then_attractor(collage_value, attractor_value, x0, sigma,
                                                    fit_cma_options(n, o.generations, o.seed * 7919 + r, threads),
                                                    o.attractor_generations, stop);
    result.evaluations += polish.evaluations;
    ++result.restarts;
    if (polish.value < best_value) best_value = polish.value, best = polish.best;
    if (o.progress && !o.progress(0.8 * (r + 1) / o.restarts)) throw Cancelled();
  }
  // The refinement's and the last search's grid: the picture's resolution, capped.
  const FitGrid fine = FitGrid::for_target(full, std::max(o.raster, std::min(o.refine_raster, int(grid.side))));
  const PixelSet fine_target = fine.downsample(full);
  if (o.start.empty() && o.final_generations > 0 && o.restarts >= kStartKinds && best_value > 1 - kAffineBelow &&
      !stop()) {
    // On the attractor itself, not the collage: the proxy's overlap term pushes a filled shape's
    // copies apart, though their overlap costs the attractor nothing. First on the search's grid,
    // then with half the steps on one of twice its cells (the coarse grid's IoU forgives the thin
    // gaps between squashed copies), and kept if the refinement's grid prefers it to the restarts'.
    Rng rng(o.seed, 1000 + o.restarts);
    const std::vector<double> x0 = ellipse_collage(target, grid, proxy, o, rng, result.evaluations);
    std::vector<double> sigma(n);
    for (int i = 0; i < n; ++i) sigma[i] = kAffineSigma[i % kParams / 2] * (i % kParams < 4 ? 1 : grid.extent);
    const CmaResult coarse = minimize_cma(attractor_value, x0, sigma,
                                          fit_cma_options(n, o.generations, o.seed * 7919 + o.restarts, threads), stop);
    for (double& v : sigma) v *= 0.5;
    const FitGrid twice = FitGrid::for_target(full, std::min(2 * o.raster, std::max(o.raster, o.refine_raster)));
    const CmaResult run = minimize_cma(attractor_on(twice, twice.downsample(full)), coarse.best, sigma,
                                       fit_cma_options(n, o.generations, o.seed * 7919 + o.restarts + 500, threads), stop);
    result.evaluations += coarse.evaluations + run.evaluations;
    ++result.restarts;
    const auto judge = attractor_on(fine, fine_target);
    if (judge(run.best, 0) < judge(best, 0)) best_value = run.value, best = run.best;
  }
  // Local refinement on the attractor: small steps about the best collage.
  if (o.refine_generations > 0 && o.start.empty() && !stop()) {
    std::vector<double> sigma(n);
    for (int i = 0; i < n; ++i) {
      const int k = i % kParams;
      sigma[i] = k < 2 ? 0.02 : k < 4 ? 0.03 : 0.01 * grid.extent;
    }
    const CmaOptions co = fit_cma_options(n, o.refine_generations, o.seed * 7919 + 999, threads);
    // On the collage, at the picture's resolution (capped): a collage exact to a pixel puts the
    // attractor within eps / (1 - s) pixels of the target (Eq. 42), which the coarse grids cannot.
    const CollageProxy fine_proxy(fine_target, o.overlap_weight);
    auto fine_value = [&](const std::vector<double>& x, int worker) {
      double excess = 0;
      const auto maps = decode_maps(x, 2, o.max_contraction, &excess);
      std::vector<PixelMap> pm;
      for (const AffineMap& m : maps) pm.push_back(fine.pixel_map(m));
      return fine_proxy(pm, scratch[worker]) + kExcessPenalty * excess;
    };
    const CmaResult run = minimize_cma(fine_value, best, sigma, co, stop);
    result.evaluations += run.evaluations;
    // Keep the refinement only if the attractor agrees, judged on the fine grid.
    const auto judge = attractor_on(fine, fine_target);
    const double before = judge(best, 0), after = judge(run.best, 0);
    if (after <= before) best = run.best;
    best_value = std::min(before, after);
  }
  // Last, the attractor's IoU itself at the picture's resolution (capped): the classic
  // attractors' thin lines make it peak within a fraction of a pixel of the exact maps, which
  // the collage (Eq. 42 bounds the distance, not the overlap) and the coarse grids cannot see.
  auto value = [&](const std::vector<double>& y, int worker) {
    double excess = 0;
    const auto maps = from_corners(y, 2, o.max_contraction, &excess);
    std::vector<PixelMap> pm;
    for (const AffineMap& m : maps) pm.push_back(fine.pixel_map(m));
    return 1.0 - chaos_iou(pm, jacobian_probabilities(maps, 2), fine_target, o.seed, scratch[worker]) + kExcessPenalty * excess;
  };
  std::vector<AffineMap> final_maps = o.start;
  if (o.start.empty()) {
    final_maps = decode_maps(best, 2, o.max_contraction, nullptr);
  } else {
    best_value = value(to_corners(final_maps, 2), 0);
  }
  if (o.final_generations > 0 && !stop()) {
    // Corners on the pixel lattice when the IoU allows (snap_corners): the plane's pixel
    // corners lie at (i, ymax - j) / pixels_per_unit.
    const auto lattice = [&](const std::vector<double>& y) {
      return snap_corners(y, 2, {0.0, fine.ymax, 0.0}, 1.0 / fine.pixels_per_unit);
    };
    // Corners that, snapped onto the lattice, draw the target exactly: no search ends better, so
    // a start with them needs none and a search that finds them stops there.
    const auto exact = [&](const std::vector<double>& y) { return value(lattice(y), 0) <= 0; };
    if (!exact(to_corners(final_maps, 2))) {
      CmaOptions co = fit_cma_options(n, o.final_generations, o.seed * 7919 + 1999, threads);
      co.tolerance = 0;  // the IoU moves in steps: flat stretches are no sign of convergence
      co.reached = exact;
      // Half a pixel per corner coordinate: the peak is that narrow.
      const CmaResult run =
          minimize_cma(value, to_corners(final_maps, 2), std::vector<double>(n, 0.5 / fine.pixels_per_unit), co, stop);
      result.evaluations += run.evaluations;
      final_maps = from_corners(run.best, 2, o.max_contraction, nullptr);
      best_value = run.value;
    }
    const auto snapped = lattice(to_corners(final_maps, 2));
    const double snapped_value = value(snapped, 0);
    if (snapped_value <= best_value + kSnapTolerance) {
      final_maps = from_corners(snapped, 2, o.max_contraction, nullptr);
      best_value = snapped_value;
    }
  }
  if (o.progress && !o.progress(1.0)) throw Cancelled();
  const auto& maps = final_maps;
  Ifs system("fit", ChannelLayout("xy"), maps);
  RenderDefaults d;
  d.window = {0.0, 0.0, double(full.width) / grid.side, double(full.height) / grid.side};
  d.width = full.width;
  d.height = full.height;
  system.set_render_defaults(d);
  result.system = std::move(system);
  result.iou = 1.0 - best_value;
  result.proxy = proxy(to_pixels(maps), scratch[0]);
  result.time_limited = deadline.passed();
  return result;
}

double attractor_iou(const Ifs& ifs, const PixelSet& target, std::uint64_t seed) {
  if (ifs.spatial_dims() != 2) throw InputError("attractor_iou needs a planar system");
  ifs.require_attractor();
  const FitGrid grid = FitGrid::for_target(target, std::max(target.width, target.height));
  std::vector<PixelMap> pm;
  for (const AffineMap& m : ifs.maps()) pm.push_back(grid.pixel_map(m));
  CollageProxy::Scratch scratch;
  return chaos_iou(pm, ifs.probabilities(), target, seed, scratch);
}

}  // namespace ifsforge
