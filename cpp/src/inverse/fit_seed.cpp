#include "fit_seed.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "fit_shared.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

constexpr double kCoverScales[] = {0.2, 0.28, 0.36, 0.45, 0.55, 0.65, 0.75, 0.88};
constexpr int kCoverTurns = 36;       // turns over the full circle
constexpr int kCoverStride = 3;       // cells between the copy centroids tried, each way
constexpr double kOutsideCost = 2.0;  // a copy cell off the target costs two newly covered ones
constexpr double kOverlapCost = 0.5;  // one on an earlier copy, half of one
constexpr double kGiveUp = 0.3;       // share of a copy's first cells off the target that ends its count
constexpr std::size_t kCoverRefined = 8;  // best copies refined by a local climb
constexpr int kCoverSlack = 2;            // cells the target grows by for the lattice
constexpr double kCoverTieBreak = 1e-3;   // below one cell: breaks ties only

struct Candidate {
  double score = -std::numeric_limits<double>::infinity();
  std::array<double, 6> p{};
};

}  // namespace

std::vector<double> self_similar_cover(const PixelSet& target, const FitGrid& grid, int maps, double max_contraction,
                                       int threads, Rng& rng, std::uint64_t& evaluations) {
  const int w = target.width, h = target.height, pad = std::max(w, h) / 2, W = w + 2 * pad, H = h + 2 * pad;
  // Cell centres in a seeded order, so that a copy's first cells are a fair sample of it.
  std::vector<std::array<double, 2>> cells;
  std::array<double, 2> centroid{0, 0};
  std::vector<std::uint8_t> on_target(std::size_t(W) * H, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (target.cells[std::size_t(y) * w + x]) {
        cells.push_back({x + 0.5, y + 0.5});
        on_target[std::size_t(y + pad) * W + x + pad] = 1;
        const auto q = grid.to_plane(x + 0.5, y + 0.5);
        centroid[0] += q[0], centroid[1] += q[1];
      }
  centroid[0] /= cells.size(), centroid[1] /= cells.size();
  for (std::size_t i = cells.size(); i > 1; --i) std::swap(cells[i - 1], cells[std::size_t(rng.uniform() * i)]);
  std::vector<std::array<double, 2>> places;  // plane points a copy's centroid is put on
  const int ox = int(rng.uniform() * kCoverStride), oy = int(rng.uniform() * kCoverStride);
  for (int y = oy; y < h; y += kCoverStride)
    for (int x = ox; x < w; x += kCoverStride)
      if (target.cells[std::size_t(y) * w + x]) places.push_back(grid.to_plane(x + 0.5, y + 0.5));
  const double turn = rng.uniform();
  std::vector<std::uint8_t> covered(on_target.size(), 0);
  const int scales = int(std::size(kCoverScales)), jobs = scales * kCoverTurns;
  const int workers = resolve_threads(threads);
  std::vector<std::vector<std::uint32_t>> stamps(workers, std::vector<std::uint32_t>(on_target.size(), 0));
  std::vector<std::uint32_t> stamp_count(workers, 0);
  auto cell_of = [&](const PixelMap& m, const std::array<double, 2>& c) {
    const double qx = m[0] * c[0] + m[1] * c[1] + m[2] + pad, qy = m[3] * c[0] + m[4] * c[1] + m[5] + pad;
    return std::size_t(std::clamp(qy, 0.0, H - 1.0)) * W + std::size_t(std::clamp(qx, 0.0, W - 1.0));
  };
  // A copy's worth: target cells it newly covers, less those off the target and on earlier
  // copies; a copy whose first cells stray too often is dropped (-infinity).
  // The target grown by kCoverSlack cells (Chebyshev): the lattice of turns and places lands
  // near a thin attractor's copies, not on them, so the lattice is judged on the grown target
  // and its best copies climb onto the exact one.
  std::vector<std::uint8_t> near_target = on_target;
  for (int pass = 0; pass < kCoverSlack; ++pass) {
    const std::vector<std::uint8_t> was = near_target;
    for (int y = 1; y + 1 < H; ++y)
      for (int x = 1; x + 1 < W; ++x)
        if (!was[std::size_t(y) * W + x])
          for (int dy = -1; dy <= 1 && !near_target[std::size_t(y) * W + x]; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if (was[std::size_t(y + dy) * W + x + dx]) {
                near_target[std::size_t(y) * W + x] = 1;
                break;
              }
  }
  auto score_of = [&](const double* p, int worker, const std::vector<std::uint8_t>& on) {
    AffineMap m;
    decode_map(p, 2, max_contraction, m);
    const PixelMap pm = grid.pixel_map(m);
    auto& stamp = stamps[worker];
    const std::uint32_t mark = ++stamp_count[worker];
    double fresh = 0, outside = 0, overlap = 0;
    std::size_t seen = 0;
    for (const auto& cell : cells) {
      ++seen;
      const std::size_t q = cell_of(pm, cell);
      if (stamp[q] == mark) continue;
      stamp[q] = mark;
      if (!on[q]) {
        if (++outside > kGiveUp * double(seen) + 8 && &on == &near_target) return -std::numeric_limits<double>::infinity();
      } else {
        (covered[q] ? overlap : fresh) += 1;
      }
    }
    // Among copies that cover alike (a symmetric target's turns and mirrors), the least turned
    // and unmirrored: the maps a person would write, and the ones colour fits expect.
    const double turned = std::abs(std::remainder(p[2], 2 * M_PI)) / M_PI + (p[0] < 0);
    return fresh - kOutsideCost * outside - kOverlapCost * overlap - kCoverTieBreak * turned;
  };
  std::vector<double> x0;
  for (int c = 0; c < maps; ++c) {
    std::vector<Candidate> best(jobs);
    parallel_jobs(std::size_t(jobs), workers, [&](std::size_t job, int worker) {
      const double s = std::min(kCoverScales[job % scales], max_contraction);
      const double angle = (double(job / scales) + turn) * 2 * M_PI / kCoverTurns;
      for (int mirror = 0; mirror < 2; ++mirror) {
        double p[6] = {mirror ? -s : s, s, angle, angle, 0, 0};
        AffineMap m;
        decode_map(p, 2, max_contraction, m);
        const double cx = m.a(0, 0) * centroid[0] + m.a(0, 1) * centroid[1];
        const double cy = m.a(1, 0) * centroid[0] + m.a(1, 1) * centroid[1];
        for (const auto& place : places) {
          p[4] = place[0] - cx;
          p[5] = place[1] - cy;
          const double score = score_of(p, worker, near_target);
          if (score > best[job].score) best[job].score = score, std::copy(p, p + 6, best[job].p.begin());
        }
      }
    });
    evaluations += std::uint64_t(jobs) * 2 * places.size();
    // The lattice of turns and places is coarse for a thin attractor (a spiral's copy 5 degrees
    // off lies mostly off it): the best few climb by halving steps of scale, turn and place.
    std::stable_sort(best.begin(), best.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    best.resize(kCoverRefined);
    parallel_jobs(best.size(), workers, [&](std::size_t k, int worker) {
      Candidate& b = best[k];
      if (!std::isfinite(b.score)) return;
      b.score = score_of(b.p.data(), worker, on_target);
      double step[3] = {0.04, 4 * M_PI / 180, 1.0 / grid.pixels_per_unit};
      for (int level = 0; level < 4; ++level, step[0] /= 2, step[1] /= 2, step[2] /= 2)
        for (bool better = true; better;) {
          better = false;
          for (int axis = 0; axis < 4; ++axis)
            for (double sign : {-1.0, 1.0}) {
              std::array<double, 6> p = b.p;
              if (axis == 0) {
                const double f = 1 + sign * step[0];
                p[0] *= f, p[1] = std::min(p[1] * f, max_contraction), p[0] = std::copysign(p[1], p[0]);
              } else if (axis == 1) {
                p[2] += sign * step[1], p[3] = p[2];
              } else {
                p[2 + axis] += sign * step[2];
              }
              const double score = score_of(p.data(), worker, on_target);
              if (score > b.score) b.score = score, b.p = p, better = true;
            }
        }
    });
    const Candidate* chosen = &best[0];
    for (const Candidate& b : best)
      if (b.score > chosen->score) chosen = &b;
    if (!std::isfinite(chosen->score)) {  // every copy strays: the largest turn-free copy on the centroid
      const double s = std::min(kCoverScales[scales / 2], max_contraction);
      best[0].p = {s, s, 0, 0, centroid[0] * (1 - s), centroid[1] * (1 - s)};
      chosen = &best[0];
    }
    AffineMap m;
    decode_map(chosen->p.data(), 2, max_contraction, m);
    const PixelMap pm = grid.pixel_map(m);
    for (const auto& cell : cells) covered[cell_of(pm, cell)] = 1;
    x0.insert(x0.end(), chosen->p.begin(), chosen->p.end());
  }
  return x0;
}

}  // namespace ifsforge
