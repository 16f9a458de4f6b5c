#include "ifsforge/inverse/fit_3d.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/inverse/cma_es.h"
#include "fit_clusters.h"
#include "fit_shared.h"
#include "fit_voxels.h"

namespace ifsforge {
namespace {

constexpr int kParams = 9;   // per map: Mx, My, Mz (signed: a negative one reflects), rx, ry, rz (radians), t (decode_map)
constexpr int kTurns = 48;   // random turns tried per map for the rotated starts

Clusters<3> voxel_clusters(const VoxelSet& t, int n, Rng& rng) {
  std::vector<std::array<double, 3>> pts;
  for (int k = 0; k < t.grid.dims[2]; ++k)
    for (int j = 0; j < t.grid.dims[1]; ++j)
      for (int i = 0; i < t.grid.dims[0]; ++i)
        if (t.cells[t.index(i, j, k)]) pts.push_back(t.grid.center(i, j, k));
  // Centres to extents: the boxes start half a voxel lower, and cluster_boxes adds a voxel above.
  auto c = cluster_boxes<3>(pts, n, t.grid.voxel_size, rng);
  auto lower = [half = 0.5 * t.grid.voxel_size](std::array<double, 6>& b) {
    for (double& v : b) v -= half;
  };
  lower(c.whole);
  for (auto& b : c.parts) lower(b);
  return c;
}

/// The initial collage: map c sends the whole target's box onto part c's box (axis-aligned).
std::vector<double> initial_collage(const Clusters<3>& boxes) {
  const auto& w = boxes.whole;
  std::vector<double> x;
  for (const auto& b : boxes.parts) {
    double s[3];
    for (int a = 0; a < 3; ++a) s[a] = std::clamp((b[a + 3] - b[a]) / std::max(w[a + 3] - w[a], 1e-12), 0.05, 0.85);
    for (double v : {s[0], s[1], s[2], 0.0, 0.0, 0.0}) x.push_back(v);
    for (int a = 0; a < 3; ++a) x.push_back(0.5 * (b[a] + b[a + 3] - (w[a] + w[a + 3]) * s[a]));
  }
  return x;
}

}  // namespace

FitResult fit_3d(const VoxelSet& full, const Fit3dOptions& o) {
  if (o.maps < 1 || o.maps > 64) throw InputError("--maps must be 1..64, got " + std::to_string(o.maps));
  if (o.restarts < 1) throw InputError("restarts: at least one CMA-ES run, got " + std::to_string(o.restarts));
  if (o.raster < 8 || o.raster > 256) throw InputError("the 3D fit raster must be 8..256 voxels, got " + std::to_string(o.raster));
  if (o.refine_raster < 8 || o.refine_raster > 512)
    throw InputError("the 3D refinement raster must be 8..512 voxels, got " + std::to_string(o.refine_raster));
  if (!(o.max_contraction > 0 && o.max_contraction < 1))
    throw InputError("the largest contraction must lie in (0, 1), got " + std::to_string(o.max_contraction));
  check_overlap_weight(o.overlap_weight);
  if (full.cells.size() != std::size_t(full.grid.dims[0]) * full.grid.dims[1] * full.grid.dims[2] ||
      !(full.grid.voxel_size > 0))
    throw InputError("the 3D target's cells do not match its grid");
  if (full.count() == 0) throw InputError("the 3D target has no voxels");
  check_start(o.start, o.maps, 3);
  FitDeadline deadline(o.time_limit);
  const int side = std::max({full.grid.dims[0], full.grid.dims[1], full.grid.dims[2]});
  const FitVoxelGrid grid = FitVoxelGrid::for_target(full, std::min(o.raster, side));
  const VoxelSet target = grid.downsample(full);
  const FitVoxelGrid fine = FitVoxelGrid::for_target(full, std::max(std::min(o.raster, side), std::min(o.refine_raster, side)));
  const VoxelSet fine_target = fine.downsample(full);
  const int threads = resolve_threads(o.threads);
  std::vector<VoxelCollageProxy::Scratch> scratch(threads);
  const VoxelCollageProxy proxy(target, o.overlap_weight);
  auto voxel_maps = [](const FitVoxelGrid& g, const std::vector<AffineMap>& maps) {
    std::vector<VoxelMap> out;
    for (const AffineMap& m : maps) out.push_back(g.voxel_map(m));
    return out;
  };
  auto collage_value = [&](const std::vector<double>& x, int worker) {
    double excess = 0;
    const auto maps = decode_maps(x, 3, o.max_contraction, &excess);
    return proxy(voxel_maps(grid, maps), scratch[worker]) + kExcessPenalty * excess;
  };
  auto attractor_value = [&](const std::vector<double>& x, int worker) {
    double excess = 0;
    const auto maps = decode_maps(x, 3, o.max_contraction, &excess);
    return 1.0 - chaos_iou_3d(voxel_maps(grid, maps), jacobian_probabilities(maps, 3), target, o.seed, scratch[worker]) +
           kExcessPenalty * excess;
  };
  auto stop = [&] { return deadline.stop(); };
  FitResult result;
  std::vector<double> best;
  double best_value = std::numeric_limits<double>::infinity();
  const int n = o.maps * kParams;
  const double extent = grid.grid.voxel_size * std::max({grid.grid.dims[0], grid.grid.dims[1], grid.grid.dims[2]});
  for (int r = 0; r < o.restarts && o.start.empty() && !stop(); ++r) {
    Rng rng(o.seed, 1000 + r);
    const Clusters<3> boxes = voxel_clusters(target, o.maps, rng);
    std::vector<double> x0 = initial_collage(boxes);
    if (r % 2) {
      // As in 2D: each map scaled by its part's share of the volume, centroid onto centroid,
      // and the best of kTurns seeded turns (and mirror images) for its own copy's distance.
      for (int c = 0; c < o.maps; ++c) {
        const auto& mc = boxes.mass[c];
        const double sc = std::clamp(std::cbrt(mc[3] / target.count()), 0.05, o.max_contraction);
        double best_score = std::numeric_limits<double>::infinity();
        for (int k = 0; k < kTurns; ++k) {
          double p[kParams] = {k % 2 ? -sc : sc, sc, sc, 0, 0, 0, 0, 0, 0};
          for (int a = 3; a < 6; ++a) p[a] = (2 * rng.uniform() - 1) * M_PI;
          AffineMap m;
          decode_map(p, 3, o.max_contraction, m);
          for (int a = 0; a < 3; ++a)
            p[6 + a] = mc[a] - (m.a(a, 0) * boxes.centroid[0] + m.a(a, 1) * boxes.centroid[1] + m.a(a, 2) * boxes.centroid[2]);
          decode_map(p, 3, o.max_contraction, m);
          const double score = proxy.copy_outside(grid.voxel_map(m));
          if (score < best_score) best_score = score, std::copy(p, p + kParams, &x0[std::size_t(c) * kParams]);
        }
      }
      result.evaluations += std::uint64_t(kTurns) * o.maps;
    }
    std::vector<double> sigma(n);
    for (int i = 0; i < n; ++i) {
      const int k = i % kParams;
      sigma[i] = k < 3 ? 0.1 : k < 6 ? (r % 2 ? 0.6 : 0.3) : 0.08 * extent;
    }
    const CmaResult polish = collage_then_attractor(collage_value, attractor_value, x0, sigma,
                                                    fit_cma_options(n, o.generations, o.seed * 7919 + r, threads),
                                                    o.attractor_generations, stop);
    result.evaluations += polish.evaluations;
    ++result.restarts;
    if (polish.value < best_value) best_value = polish.value, best = polish.best;
    if (o.progress && !o.progress(0.7 * (r + 1) / o.restarts)) throw Cancelled();
  }
  std::vector<AffineMap> final_maps = o.start.empty() ? decode_maps(best, 3, o.max_contraction, nullptr) : o.start;
  // Last, the attractor's IoU on the finer grid, by the copies' corners (half a voxel steps).
  auto fine_value = [&](const std::vector<double>& y, int worker) {
    double excess = 0;
    const auto maps = from_corners(y, 3, o.max_contraction, &excess);
    return 1.0 - chaos_iou_3d(voxel_maps(fine, maps), jacobian_probabilities(maps, 3), fine_target, o.seed,
                              scratch[worker]) + kExcessPenalty * excess;
  };
  best_value = fine_value(to_corners(final_maps, 3), 0);
  auto lattice = [&](const std::vector<double>& y) { return snap_corners(y, 3, fine.grid.origin, fine.grid.voxel_size); };
  // Corners that, snapped onto the lattice, draw the target exactly: no search ends better, so a
  // start with them needs none and a search that finds them stops there.
  auto exact = [&](const std::vector<double>& y) { return fine_value(lattice(y), 0) <= 0; };
  if (o.final_generations > 0 && !stop() && !exact(to_corners(final_maps, 3))) {
    CmaOptions co = fit_cma_options(o.maps * 12, o.final_generations, o.seed * 7919 + 1999, threads);
    co.tolerance = 0;  // the IoU moves in steps: flat stretches are no sign of convergence
    co.reached = exact;
    const CmaResult run = minimize_cma(fine_value, to_corners(final_maps, 3),
                                       std::vector<double>(std::size_t(o.maps) * 12, 0.5 * fine.grid.voxel_size), co, stop);
    result.evaluations += run.evaluations;
    final_maps = from_corners(run.best, 3, o.max_contraction, nullptr);
    best_value = run.value;
  }
  // Corners on the voxel lattice when the IoU allows (snap_corners).
  const std::vector<double> snapped = lattice(to_corners(final_maps, 3));
  const double snapped_value = fine_value(snapped, 0);
  if (snapped_value <= best_value + kSnapTolerance) {
    final_maps = from_corners(snapped, 3, o.max_contraction, nullptr);
    best_value = snapped_value;
  }
  if (o.progress && !o.progress(1.0)) throw Cancelled();
  Ifs system("fit", ChannelLayout("xyz"), final_maps);
  const Box3 box = full.grid.box();
  system.set_description("fitted to a target on the box " + std::to_string(box[0]) + " " + std::to_string(box[1]) + " " +
                         std::to_string(box[2]) + " " + std::to_string(box[3]) + " " + std::to_string(box[4]) + " " +
                         std::to_string(box[5]));
  result.system = std::move(system);
  result.iou = 1.0 - best_value;
  result.proxy = proxy(voxel_maps(grid, final_maps), scratch[0]);
  result.time_limited = deadline.passed();
  return result;
}

double attractor_iou_3d(const Ifs& ifs, const VoxelSet& target, std::uint64_t seed) {
  if (ifs.spatial_dims() != 3) throw InputError("attractor_iou_3d needs a system with xyz space");
  if (target.cells.size() != std::size_t(target.grid.dims[0]) * target.grid.dims[1] * target.grid.dims[2])
    throw InputError("the 3D target's cells do not match its grid");
  ifs.require_attractor();
  FitVoxelGrid g;
  g.grid = target.grid;
  std::vector<VoxelMap> maps;
  for (const AffineMap& m : ifs.maps()) {
    AffineMap spatial(3);  // the xyz block: extra channels never move the points
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) spatial.a(r, c) = m.a(r, c);
      spatial.b(r) = m.b(r);
    }
    maps.push_back(g.voxel_map(spatial));
  }
  VoxelCollageProxy::Scratch scratch;
  return chaos_iou_3d(maps, ifs.probabilities(), target, seed, scratch);
}

}  // namespace ifsforge
