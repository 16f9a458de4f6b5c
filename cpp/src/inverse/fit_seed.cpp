#include "fit_seed.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "fit_clusters.h"
#include "fit_moments.h"
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
constexpr int kCoverBeamCopies = 32;      // copies the beam's covers may hold together: fewer covers for more maps
constexpr int kCoverSlack = 2;            // cells the target grows by for the lattice
constexpr double kCoverTieBreak = 1e-3;   // below one cell: breaks ties only
constexpr std::size_t kMostParts = 32;    // largest parts of the target whose moments give candidates
constexpr std::size_t kPartCells = 4;     // fewer cells give no orientation worth trying
constexpr std::size_t kRemainderParts = 4;  // largest parts of a cover's remainder whose moments give candidates
constexpr std::size_t kComplements = 4;   // largest parts whose complement is a piece too
constexpr std::size_t kJudgedPixels = 65536;  // picture pixels at most that the climb copies (evenly spread)

struct Candidate {
  double score = -std::numeric_limits<double>::infinity();
  std::array<double, 6> p{};
};

/// The plane point at the centre of cell q of a grid of `grid`'s cells, `W` wide, padded by `pad`.
std::array<double, 2> padded_plane(const FitGrid& grid, int W, int pad, std::size_t q) {
  return grid.to_plane(int(q % W) - pad + 0.5, int(q / W) - pad + 0.5);
}

/// The moment maps (fit_moments.h) over the full circle of each piece (plane points) large enough.
std::vector<std::array<double, 6>> piece_maps(const std::vector<std::vector<std::array<double, 2>>>& pieces,
                                              const Moments& whole, double max_contraction) {
  std::vector<std::array<double, 6>> out;
  for (const auto& piece : pieces)
    if (piece.size() >= kPartCells)
      for (const auto& p : moment_maps(whole, moments_of(piece), max_contraction, kCoverTurns)) out.push_back(p);
  return out;
}

/// The moment maps (fit_moments.h) of the target's pieces: its parts once grown by 0 to
/// kCoverSlack cells (`grown`, padded by `pad`; the first is the target), the whole less each of
/// the largest of them, and its k-means clusters into `maps`.
std::vector<std::array<double, 6>> moment_candidates(const PixelSet& target, const FitGrid& grid,
                                                     const std::vector<std::vector<std::uint8_t>>& grown, int pad,
                                                     int maps, double max_contraction, Rng& rng) {
  const int W = target.width + 2 * pad, H = target.height + 2 * pad;
  const std::vector<std::uint8_t>& on = grown[0];
  auto plane = [&](std::size_t q) { return padded_plane(grid, W, pad, q); };
  std::vector<std::array<double, 2>> whole;
  for (std::size_t q = 0; q < on.size(); ++q)
    if (on[q]) whole.push_back(plane(q));
  std::vector<std::vector<std::array<double, 2>>> pieces;
  // A gap narrower than the growth joins two parts: each growth finds the parts of its scale.
  std::vector<std::uint8_t> in_part(on.size());
  for (const auto& mask : grown) {
    const auto parts = mask_parts(mask, on, W, H, kMostParts);
    for (const auto& part : parts) {
      pieces.emplace_back();
      for (std::size_t q : part) pieces.back().push_back(plane(q));
    }
    // The whole less one of its largest parts: the other copies together (with two maps, exactly
    // the other copy, as a spiral's large turned copy is the whole less its small one).
    for (std::size_t k = 0; k < std::min(parts.size(), kComplements); ++k) {
      std::fill(in_part.begin(), in_part.end(), 0);
      for (std::size_t q : parts[k]) in_part[q] = 1;
      pieces.emplace_back();
      for (std::size_t q = 0; q < on.size(); ++q)
        if (on[q] && !in_part[q]) pieces.back().push_back(plane(q));
    }
  }
  if (maps > 1) {  // each cell to its nearest cluster centroid: the k-means partition
    const auto parts = cluster_parts<2>(whole, cluster_boxes<2>(whole, maps, 1.0 / grid.pixels_per_unit, rng));
    pieces.insert(pieces.end(), parts.begin(), parts.end());
  }
  return piece_maps(pieces, moments_of(whole), max_contraction);
}

/// The moment maps of what a cover leaves of the target `on` (W x H, padded by `pad`) beside
/// `covered`: the whole remainder and its largest parts once grown by a cell, the copies still
/// missing (a leaf's second side branch once its tip and first branch are covered).
std::vector<std::array<double, 6>> remainder_candidates(const std::vector<std::uint8_t>& on,
                                                        const std::vector<std::uint8_t>& covered, int W, int H, int pad,
                                                        const FitGrid& grid, const Moments& whole,
                                                        double max_contraction) {
  std::vector<std::uint8_t> left(on.size());
  std::vector<std::vector<std::array<double, 2>>> pieces(1);
  for (std::size_t q = 0; q < on.size(); ++q)
    if ((left[q] = on[q] && !covered[q])) pieces[0].push_back(padded_plane(grid, W, pad, q));
  for (const auto& part : mask_parts(grow_cells(left, W, H), left, W, H, kRemainderParts)) {
    pieces.emplace_back();
    for (std::size_t q : part) pieces.back().push_back(padded_plane(grid, W, pad, q));
  }
  return piece_maps(pieces, whole, max_contraction);
}

/// A copy's worth judged on one grid: target cells it newly covers (not in a cover's `covered`),
/// less those it puts off the target (or off `on`, a grown target) and on earlier copies.
class CopyJudge {
 public:
  /// `target` on `grid`; the copies are of `points` (grid cell units), by default the cells' centres.
  CopyJudge(const FitGrid& grid, const PixelSet& target, int workers, std::vector<std::array<double, 2>> points = {})
      : points(std::move(points)), grid_(grid), pad_(std::max(target.width, target.height) / 2),
        w_(target.width + 2 * pad_), h_(target.height + 2 * pad_), on_(std::size_t(w_) * h_, 0),
        stamps_(workers, std::vector<std::uint32_t>(on_.size(), 0)), marks_(workers, 0) {
    const bool centres = this->points.empty();
    for (int y = 0; y < target.height; ++y)
      for (int x = 0; x < target.width; ++x)
        if (target.cells[std::size_t(y) * target.width + x]) {
          if (centres) this->points.push_back({x + 0.5, y + 0.5});
          on_[std::size_t(y + pad_) * w_ + x + pad_] = 1;
        }
  }
  std::vector<std::array<double, 2>> points;  ///< what is copied, in the order it is judged
  const std::vector<std::uint8_t>& on() const { return on_; }
  int pad() const { return pad_; }
  int width() const { return w_; }
  int height() const { return h_; }
  /// The cells of a cover of no copies yet.
  std::vector<std::uint8_t> nothing_covered() const { return std::vector<std::uint8_t>(on_.size(), 0); }
  /// The worth of w(target) against `on` (on() or a grown copy of it) and the cells `covered`
  /// already; with `give_up`, -infinity once its first cells stray too often.
  double worth(const AffineMap& w, int worker, const std::vector<std::uint8_t>& on,
               const std::vector<std::uint8_t>& covered, bool give_up) {
    const PixelMap pm = grid_.pixel_map(w);
    auto& stamp = stamps_[worker];
    const std::uint32_t mark = ++marks_[worker];
    double fresh = 0, outside = 0, overlap = 0;
    std::size_t seen = 0;
    for (const auto& point : points) {
      ++seen;
      const std::size_t q = cell_of(pm, point);
      if (stamp[q] == mark) continue;
      stamp[q] = mark;
      if (!on[q]) {
        if (++outside > kGiveUp * double(seen) + 8 && give_up) return -std::numeric_limits<double>::infinity();
      } else {
        (covered[q] ? overlap : fresh) += 1;
      }
    }
    return fresh - kOutsideCost * outside - kOverlapCost * overlap;
  }
  void cover(const AffineMap& w, std::vector<std::uint8_t>& covered) const {
    const PixelMap pm = grid_.pixel_map(w);
    for (const auto& point : points) covered[cell_of(pm, point)] = 1;
  }

 private:
  std::size_t cell_of(const PixelMap& m, const std::array<double, 2>& c) const {
    const double qx = m[0] * c[0] + m[1] * c[1] + m[2] + pad_, qy = m[3] * c[0] + m[4] * c[1] + m[5] + pad_;
    return std::size_t(std::clamp(qy, 0.0, h_ - 1.0)) * w_ + std::size_t(std::clamp(qx, 0.0, w_ - 1.0));
  }
  FitGrid grid_;
  int pad_, w_, h_;
  std::vector<std::uint8_t> on_;
  std::vector<std::vector<std::uint32_t>> stamps_;
  std::vector<std::uint32_t> marks_;
};

/// A cover under construction: its copies' parameters, the cells they cover on either grid, and
/// the summed worth of its copies (each judged against those before it, on the picture's pixels).
struct Cover {
  std::vector<double> x0;
  std::vector<std::uint8_t> coarse, fine;
  double worth = 0;
};

}  // namespace

std::vector<double> self_similar_cover(const PixelSet& full, const PixelSet& target, const FitGrid& grid, int maps,
                                       int judge_raster, double max_contraction, bool beam, int threads, Rng& rng,
                                       std::uint64_t& evaluations, const std::function<bool()>& stop) {
  const int w = target.width, h = target.height, workers = resolve_threads(threads);
  // The lattice is judged on the search's grid, in a seeded order of its cells so that a copy's
  // first cells are a fair sample of it. The climb and the choice copy the picture's own pixels:
  // copies of the cells' centres fall a fraction of a cell beside a thin target's cells, so that a
  // spiral's true turned copy scores no better than the copy of that copy.
  CopyJudge coarse(grid, target, workers);
  auto& cells = coarse.points;
  for (std::size_t i = cells.size(); i > 1; --i) std::swap(cells[i - 1], cells[std::size_t(rng.uniform() * i)]);
  const FitGrid fine_grid = FitGrid::for_target(full, std::min(std::max(full.width, full.height), judge_raster));
  std::vector<std::array<double, 2>> pixels;  // the picture's pixels in the judging grid's cells
  const std::size_t stride = (full.count() + kJudgedPixels - 1) / kJudgedPixels;
  const double f = fine_grid.pixels_per_unit / fine_grid.side;
  for (std::size_t i = 0, seen = 0; i < full.cells.size(); ++i)
    if (full.cells[i] && seen++ % stride == 0) pixels.push_back({(i % full.width + 0.5) * f, (i / full.width + 0.5) * f});
  CopyJudge fine(fine_grid, fine_grid.downsample(full), workers, std::move(pixels));
  std::vector<std::array<double, 2>> cell_points;
  for (const auto& c : cells) cell_points.push_back(grid.to_plane(c[0], c[1]));
  const Moments whole = moments_of(cell_points);
  const std::array<double, 2>& centroid = whole.centroid;
  std::vector<std::array<double, 2>> places;  // plane points a copy's centroid is put on
  std::vector<std::size_t> place_cells;       // their cells on the coarse judge's padded grid
  const int ox = int(rng.uniform() * kCoverStride), oy = int(rng.uniform() * kCoverStride);
  for (int y = oy; y < h; y += kCoverStride)
    for (int x = ox; x < w; x += kCoverStride)
      if (target.cells[std::size_t(y) * w + x]) {
        places.push_back(grid.to_plane(x + 0.5, y + 0.5));
        place_cells.push_back(std::size_t(y + coarse.pad()) * coarse.width() + x + coarse.pad());
      }
  const double turn = rng.uniform();
  const int scales = int(std::size(kCoverScales)), jobs = scales * kCoverTurns;
  // The target grown by kCoverSlack cells (Chebyshev): the lattice of turns and places lands
  // near a thin attractor's copies, not on them, so the lattice is judged on the grown target
  // and its best copies climb onto the exact one.
  std::vector<std::vector<std::uint8_t>> grown = {coarse.on()};  // grown by 0, 1, ... kCoverSlack cells
  for (int pass = 0; pass < kCoverSlack; ++pass) grown.push_back(grow_cells(grown.back(), coarse.width(), coarse.height()));
  const std::vector<std::uint8_t>& near_target = grown.back();
  const std::vector<std::array<double, 6>> shaped =
      moment_candidates(target, grid, grown, coarse.pad(), maps, max_contraction, rng);
  auto score_of = [&](const double* p, int worker, const Cover& cover, bool lattice) {
    AffineMap m;
    decode_map(p, 2, max_contraction, m);
    const double worth = lattice ? coarse.worth(m, worker, near_target, cover.coarse, true)
                                 : fine.worth(m, worker, fine.on(), cover.fine, false);
    // Among copies that cover alike (a symmetric target's turns and mirrors), the least turned
    // and unmirrored: the maps a person would write, and the ones colour fits expect.
    const double turned = std::abs(std::remainder(p[2], 2 * M_PI)) / M_PI + (p[0] < 0);
    return worth - kCoverTieBreak * turned;
  };
  // The copies worth adding to `cover` next, climbed, best first: the best few of the lattice's
  // and the moment maps' or, `diverse`, the best of each lattice scale (the moment maps by their
  // nearest), so that a cover may begin with a copy smaller than the one covering most.
  auto next_copies = [&](const Cover& cover, bool diverse) {
    // A copy still missing lies mostly where the cover has not been: its centroid is put on the
    // places left uncovered (all of them when none is).
    std::vector<std::array<double, 2>> open;
    for (std::size_t k = 0; k < places.size(); ++k)
      if (!cover.coarse[place_cells[k]]) open.push_back(places[k]);
    if (open.empty()) open = places;
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
        for (const auto& place : open) {
          p[4] = place[0] - cx;
          p[5] = place[1] - cy;
          const double score = score_of(p, worker, cover, true);
          if (score > best[job].score) best[job].score = score, std::copy(p, p + 6, best[job].p.begin());
        }
      }
    });
    evaluations += std::uint64_t(jobs) * 2 * open.size();
    // The lattice of turns and places is coarse for a thin attractor (a spiral's copy 5 degrees
    // off lies mostly off it): the best few climb by halving steps of scale, turn and place.
    // Each lattice job's best copy and every moment map of the pieces (exact turns and scales, off
    // the lattice) are judged again by the picture's pixels, and the best few climb.
    for (const auto& p : shaped) best.push_back({0, p});
    if (!cover.x0.empty()) {
      for (const auto& p : remainder_candidates(coarse.on(), cover.coarse, coarse.width(), coarse.height(), coarse.pad(),
                                                grid, whole, max_contraction))
        best.push_back({0, p});
      for (const auto& p : symmetric_copies(cover.x0, whole)) best.push_back({0, p});
    }
    parallel_jobs(best.size(), workers, [&](std::size_t k, int worker) {
      if (std::isfinite(best[k].score)) best[k].score = score_of(best[k].p.data(), worker, cover, false);
    });
    evaluations += best.size();
    auto bucket = [&](const Candidate& c) {
      int nearest = 0;
      for (int k = 1; k < scales; ++k)
        if (std::abs(kCoverScales[k] - std::abs(c.p[1])) < std::abs(kCoverScales[nearest] - std::abs(c.p[1]))) nearest = k;
      return nearest;
    };
    std::stable_sort(best.begin(), best.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    if (diverse) {  // the first of each bucket, in the order of their scores
      std::vector<Candidate> kept;
      std::vector<bool> taken(scales, false);
      for (const Candidate& c : best)
        if (!taken[bucket(c)]) taken[bucket(c)] = true, kept.push_back(c);
      best = std::move(kept);
    }
    if (best.size() > kCoverRefined) best.resize(kCoverRefined);
    parallel_jobs(best.size(), workers, [&](std::size_t k, int worker) {
      Candidate& b = best[k];
      if (!std::isfinite(b.score)) return;
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
              const double score = score_of(p.data(), worker, cover, false);
              if (score > b.score) b.score = score, b.p = p, better = true;
            }
        }
    });
    std::stable_sort(best.begin(), best.end(), [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    if (best.empty() || !std::isfinite(best[0].score)) {  // every copy strays: the largest turn-free copy on the centroid
      const double s = std::min(kCoverScales[scales / 2], max_contraction);
      best.assign(1, {0, {s, s, 0, 0, centroid[0] * (1 - s), centroid[1] * (1 - s)}});
    }
    return best;
  };
  auto add = [&](Cover& cover, const Candidate& copy) {
    AffineMap m;
    decode_map(copy.p.data(), 2, max_contraction, m);
    coarse.cover(m, cover.coarse);
    fine.cover(m, cover.fine);
    cover.x0.insert(cover.x0.end(), copy.p.begin(), copy.p.end());
    cover.worth += copy.score;
  };
  // Greedy from each first copy of the beam (one of each scale, the best scales while the covers'
  // copies stay within kCoverBeamCopies, none after the deadline); the cover worth most wins.
  // Without the beam, the one greedy cover from the copy worth most.
  const Cover empty{{}, coarse.nothing_covered(), fine.nothing_covered(), 0};
  std::vector<Cover> covers;
  const std::size_t width = beam ? std::size_t(std::max(2, kCoverBeamCopies / maps)) : 1;
  for (const Candidate& first : next_copies(empty, beam && maps > 1)) {
    if (!covers.empty() && (!std::isfinite(first.score) || covers.size() == width || stop())) break;
    covers.push_back(empty);
    add(covers.back(), first);
    for (int c = 1; c < maps; ++c) add(covers.back(), next_copies(covers.back(), false)[0]);
  }
  const Cover* chosen = &covers[0];
  for (const Cover& c : covers)
    if (c.worth > chosen->worth) chosen = &c;
  return chosen->x0;
}

}  // namespace ifsforge
