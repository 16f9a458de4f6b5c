#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <vector>

#include "ifsforge/core/parallel.h"
#include "ifsforge/model/ifs.h"
#include "affine_walk.h"

namespace ifsforge {
namespace {

// A segment of the walk after the first starts from the start point kConverge steps early, on
// the random draws the walk takes there: a system that contracts on average forgets where it
// started, and in double precision the guess lands exactly on the true orbit within a few
// hundred steps. Where the segment before ends is the check: any difference (a slowly
// contracting system) and the walk runs on one core instead.
constexpr std::size_t kConverge = 1024;
// Points per segment at least: on fewer, waking a thread costs more than it saves.
constexpr std::size_t kSegmentMin = 8192;
constexpr int kMostValues = 8;

/// The least and greatest of each value so far, the first of equal ones kept (as std::min,
/// std::max and a scan by min_element/max_element keep it).
struct Extent {
  std::array<double, kMostValues> lo, hi;
  Extent() {
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
  }
  void add(const double* lows, const double* highs, int k) {
    for (int c = 0; c < k; ++c) {
      if (lows[c] < lo[c]) lo[c] = lows[c];
      if (hi[c] < highs[c]) hi[c] = highs[c];
    }
  }
};

/// The extent over `segments` pieces of the walk side by side; false if a guessed piece did not
/// meet the one before it (or a point was not finite).
template <int N>
bool segmented_extent(const Ifs& ifs, std::size_t count, std::uint64_t seed, int k, const ExtentView& view,
                      int segments, Extent& total) {
  const affine_walk::Walker<N> walker(ifs);
  const MapChain chain(ifs);
  const Point start = affine_walk::start(ifs, N);
  struct Piece {
    Extent extent;
    Point first{}, last{};  // where the walk stands before its first point and after its last
    std::uint32_t first_map = 0, last_map = 0;
    bool finite = true;
  };
  std::vector<Piece> pieces(static_cast<std::size_t>(segments));
  auto begin = [&](std::size_t s) { return count * s / static_cast<std::size_t>(segments); };
  parallel_jobs(pieces.size(), segments, [&](std::size_t s, int) {
    Piece& piece = pieces[s];
    Rng rng(seed, 0);
    std::uint32_t map = chain.start(rng);
    Point p = start;
    std::size_t settle = affine_walk::kSettle;
    if (s > 0) {
      for (std::size_t i = 0, skipped = affine_walk::kSettle + begin(s) - kConverge; i < skipped; ++i) rng.next();
      settle = kConverge;
    }
    for (std::size_t i = 0; i < settle; ++i) walker.step(chain, rng, map, p);
    piece.first = p;
    piece.first_map = map;
    double values[kMostValues];
    for (std::size_t i = begin(s), end = begin(s + 1); i < end; ++i) {
      walker.step(chain, rng, map, p);
      if (!walker.finite(p)) {
        piece.finite = false;
        return;
      }
      view(p, values);
      piece.extent.add(values, values, k);
    }
    piece.last = p;
    piece.last_map = map;
  });
  for (std::size_t s = 0; s < pieces.size(); ++s) {
    if (!pieces[s].finite) return false;
    // Bit for bit (a -0 is not a 0: it can change a later sum's sign).
    if (s > 0 && (pieces[s].first_map != pieces[s - 1].last_map ||
                  std::memcmp(pieces[s].first.data(), pieces[s - 1].last.data(), N * sizeof(double)) != 0))
      return false;
  }
  for (const Piece& piece : pieces) total.add(piece.extent.lo.data(), piece.extent.hi.data(), k);
  return true;
}

}  // namespace

void sample_extent(const Ifs& ifs, std::size_t count, std::uint64_t seed, int k, const ExtentView& view, double* lo,
                   double* hi, int threads) {
  const std::size_t most = count / kSegmentMin;
  const int segments = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(resolve_threads(threads)), most));
  Extent total;
  bool done = false;
  if (segments > 1 && !ifs.polar() && ifs.dim() == 2) done = segmented_extent<2>(ifs, count, seed, k, view, segments, total);
  if (segments > 1 && !ifs.polar() && ifs.dim() == 3) done = segmented_extent<3>(ifs, count, seed, k, view, segments, total);
  if (!done) {
    total = Extent();
    double values[kMostValues];
    sample_attractor(ifs, count, seed, [&](const Point& p) {
      view(p, values);
      total.add(values, values, k);
    });
  }
  std::copy(total.lo.begin(), total.lo.begin() + k, lo);
  std::copy(total.hi.begin(), total.hi.begin() + k, hi);
}

}  // namespace ifsforge
