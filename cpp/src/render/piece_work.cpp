#include "ifsforge/render/piece_work.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/model/capabilities.h"

namespace ifsforge {

double estimated_pieces(const Ifs& ifs, double ratio, int max_depth) {
  const std::size_t n = ifs.size();
  if (!(ratio > 1.0)) return 1.0;
  std::vector<double> s;
  for (const AffineMap& m : ifs.maps()) s.push_back(spatial_shrink(m, ifs.spatial_dims()));
  double shortest = std::numeric_limits<double>::infinity();  // smallest log(1/s_i) of a map that shrinks
  for (double f : s) {
    if (!(f < 1.0)) return std::numeric_limits<double>::infinity();
    if (f > 0.0) shortest = std::min(shortest, -std::log(f));
  }
  if (!std::isfinite(shortest)) return 1.0 + static_cast<double>(n);  // every map collapses to a point
  // N on a grid of log sizes (16 cells per smallest step, at most 4096): steps rounded down,
  // so the count errs high.
  const double total = std::log(ratio);
  const double h = std::max(shortest / 16.0, total / 4096.0);
  const std::size_t cells = static_cast<std::size_t>(std::ceil(total / h));
  std::vector<std::size_t> step(n);
  for (std::size_t i = 0; i < n; ++i)
    step[i] = s[i] > 0.0 ? std::max<std::size_t>(1, static_cast<std::size_t>(-std::log(s[i]) / h)) : cells + 1;
  // below[x]: the pieces of a subtree whose root still has x cells to shrink, one level deeper
  // per pass from the deepest (a leaf whatever its size) up to the root.
  std::vector<double> below(cells + 1, 1.0), level(cells + 1, 1.0);
  for (int depth = max_depth - 1; depth >= 0; --depth) {
    for (std::size_t x = 1; x <= cells; ++x) {
      double sum = 1.0;
      for (std::size_t i = 0; i < n; ++i) sum += step[i] >= x ? 1.0 : below[x - step[i]];
      level[x] = std::min(sum, 1e300);
    }
    below.swap(level);
  }
  return below[cells];
}

PieceBudget::PieceBudget(const Ifs& ifs, const Frame& frame, double leaf, std::string algorithm)
    : ifs_(ifs), width_(frame.width()), height_(frame.height()), algorithm_(std::move(algorithm)) {
  limit_ = std::max(kMinPieceWork, kPiecesPerPixel * width_ * height_);
  const Bounds b = ifs.attractor_bounds(1u << 12);
  const int spatial = ifs.spatial_dims();
  double extent = 0.0, box_area = 1.0;
  for (int c = 0; c < spatial; ++c) {
    extent += (b.hi[c] - b.lo[c]) * (b.hi[c] - b.lo[c]);
    if (c < 2) box_area *= b.hi[c] - b.lo[c];
  }
  extent = std::sqrt(extent) / frame.pixel_size();  // the box's diagonal, in pixels
  double pieces = estimated_pieces(ifs, extent / leaf);
  // A window inside the attractor's box sees about its share of the pieces (the others are
  // off the image, pruned).
  const Window& w = frame.window();
  const double window_area = (w.xmax - w.xmin) * (w.ymax - w.ymin);
  if (spatial == 2 && box_area > 0.0 && window_area < box_area) pieces *= window_area / box_area;
  if (pieces > kEstimateSlack * limit_) refuse(pieces, "would split");
}

void PieceBudget::spend(std::uint64_t pieces) {
  const std::uint64_t total = spent_.fetch_add(pieces, std::memory_order_relaxed) + pieces;
  if (static_cast<double>(total) > limit_) refuse(static_cast<double>(total), "has split");
}

void PieceBudget::refuse(double pieces, const char* how) const {
  double overlap = 0.0;
  for (std::size_t i = 0; i < ifs_.size(); ++i) overlap += std::abs(ifs_.map(i).determinant(ifs_.spatial_dims()));
  char text[240];
  std::snprintf(text, sizeof text,
                " 10^%.1f pieces on the way to the pixel at %dx%d, more than the %.0f per pixel it may visit "
                "(sum of |det| = %.3g: %s)",
                std::isfinite(pieces) ? std::log10(pieces) : 300.0, width_, height_, kPiecesPerPixel, overlap,
                overlap > 1.0 ? "they overlap and multiply faster than the pixels"
                              : "they shrink slowly or overlap in the image");
  throw InputError(algorithm_ + " " + how + " system '" + ifs_.name() + "' into" + text +
                   "; use chaos or prr, or a smaller size");
}

}  // namespace ifsforge
