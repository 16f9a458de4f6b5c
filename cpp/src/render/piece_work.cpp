#include "ifsforge/render/piece_work.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"

namespace ifsforge {

double estimated_pieces(const Ifs& ifs, double ratio) {
  const std::size_t n = ifs.size();
  if (!(ratio > 1.0)) return 1.0;
  const auto s = ifs.spatial_contraction_factors();
  double shortest = std::numeric_limits<double>::infinity();  // smallest log(1/s_i) of a map that shrinks
  for (double f : s) {
    if (!(f < 1.0)) return std::numeric_limits<double>::infinity();
    if (f > 0.0) shortest = std::min(shortest, -std::log(f));
  }
  if (!std::isfinite(shortest)) return 1.0 + static_cast<double>(n);  // every map collapses to a point
  // N on a grid of log sizes, 64 cells per smallest step; steps rounded down, so the count
  // errs high.
  const double total = std::log(ratio);
  double h = shortest / 64.0;
  std::size_t cells = static_cast<std::size_t>(std::ceil(total / h));
  constexpr std::size_t kMaxCells = 1u << 20;
  if (cells > kMaxCells) {
    cells = kMaxCells;
    h = total / static_cast<double>(cells);
  }
  std::vector<std::size_t> step(n);
  for (std::size_t i = 0; i < n; ++i)
    step[i] = s[i] > 0.0 ? std::max<std::size_t>(1, static_cast<std::size_t>(-std::log(s[i]) / h)) : cells + 1;
  // count[x]: the pieces of a subtree whose root still has x cells to shrink (x = 0: a leaf).
  std::vector<double> count(cells + 1, 1.0);
  for (std::size_t x = 1; x <= cells; ++x) {
    double sum = 1.0;
    for (std::size_t i = 0; i < n; ++i) sum += step[i] >= x ? 1.0 : count[x - step[i]];
    count[x] = std::min(sum, 1e300);
  }
  return count[cells];
}

void check_piece_work(const Ifs& ifs, const Frame& frame, double leaf, double bytes_per_piece,
                      const std::string& algorithm) {
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
  const double pixels = static_cast<double>(frame.width()) * frame.height();
  const double limit = std::max(kMinPieceWork, kPiecesPerPixel * pixels);
  if (pieces > limit) {
    char text[160];
    double total = 0.0;
    for (std::size_t i = 0; i < ifs.size(); ++i) total += std::abs(ifs.map(i).determinant(spatial));
    std::snprintf(text, sizeof text, "about 10^%.0f pieces (sum of |det| = %.3g: they overlap and multiply faster than the pixels)",
                  std::isfinite(pieces) ? std::log10(pieces) : 300.0, total);
    throw InputError(algorithm + " would split system '" + ifs.name() + "' into " + text + " at " +
                     std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                     ", more than it may visit there (" + std::to_string(static_cast<long long>(limit)) +
                     "); use chaos or prr, or a smaller size");
  }
  check_memory(pieces * bytes_per_piece, algorithm + " of system '" + ifs.name() + "' at " +
                                             std::to_string(frame.width()) + "x" + std::to_string(frame.height()));
}

}  // namespace ifsforge
