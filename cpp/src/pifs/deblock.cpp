#include "ifsforge/pifs/deblock.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/planes.h"
#include "decode_steps.h"

namespace ifsforge {
namespace {

constexpr std::size_t kJobs = 64;  // leaf chunks per pass

/// How hard an edge is smoothed, chosen on the training photos of cpp/bench/pifs_zoom.py: at the
/// plane's own size and below, a gentle blend (⅛ of the step moves to each side at 1×), and only
/// where both sides are smooth (each side's own step over one ramp width under `flat` levels),
/// since a code fine enough for small cells puts its block edges on true detail; magnified, the
/// edges are magnified too and are smoothed fully.
struct DeblockStrength {
  float gain;  ///< scales the ramp (1: the step halved at the edge)
  float flat;  ///< largest step on either side, in 8-bit levels, that still lets the edge be smoothed
};
constexpr DeblockStrength kNative{0.5f, 6.f};
constexpr DeblockStrength kMagnified{1.5f, INFINITY};

}  // namespace

void deblock_leaves(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& r, bool vertical,
                    std::size_t begin, std::size_t end) {
  auto scaled = [&](int v) { return log_scale >= 0 ? v << log_scale : v >> -log_scale; };
  const DeblockStrength strength = log_scale > 0 ? kMagnified : kNative;
  // The step δ between the two pixels at an edge is spread as a linear ramp over `w` pixels on
  // each side, w = the scale, so a magnified decode loses its block edges as the original does.
  const int w = std::max(1, scaled(1));
  std::vector<float> weight(w);
  for (int k = 0; k < w; ++k) weight[k] = strength.gain * 0.5f * float(w - k) / float(w + 1);
  // p1 p0 | q0 q1, one ramp width apart: the edge is smoothed where neither side steps by more.
  auto smooth = [&](float p1, float p0, float q0, float q1) {
    return std::max(std::abs(p1 - p0), std::abs(q1 - q0)) < strength.flat;
  };
  for (std::size_t i = begin; i < end; ++i) {
    const PifsLeaf& leaf = plane.leaves[i];
    const int n = scaled(1 << leaf.log_size);
    if (n < 4 * w) continue;
    const int x0 = scaled(leaf.x), y0 = scaled(leaf.y);
    if (vertical && x0 >= w)
      for (int v = 0; v < n; ++v) {
        float* p = r.row(y0 + v) + x0;
        if (x0 < 2 * w || !smooth(p[-1 - w], p[-1], p[0], p[w])) continue;
        const float delta = p[0] - p[-1];
        for (int k = 0; k < w; ++k) {
          p[-1 - k] += delta * weight[k];
          p[k] -= delta * weight[k];
        }
      }
    if (!vertical && y0 >= w)
      for (int u = 0; u < n; ++u) {
        const int x = x0 + u;
        if (y0 < 2 * w || !smooth(r.row(y0 - 1 - w)[x], r.row(y0 - 1)[x], r.row(y0)[x], r.row(y0 + w)[x]))
          continue;
        const float delta = r.row(y0)[x] - r.row(y0 - 1)[x];
        for (int k = 0; k < w; ++k) {
          r.row(y0 - 1 - k)[x] += delta * weight[k];
          r.row(y0 + k)[x] -= delta * weight[k];
        }
      }
  }
}

void deblock(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& r, int threads) {
  // Every inner edge is the left or top edge of exactly one leaf. The vertical edges go first,
  // then the horizontal ones: the ramps of one direction touch disjoint pixels (cells under 4w
  // are left), and the side pixels each edge reads lie outside every other ramp of its
  // direction, so each pass gives the same result in any order, on any number of threads.
  const std::size_t count = plane.leaves.size();
  threads = pass_threads(threads, double(r.width) * r.height);
  for (const bool vertical : {true, false})
    parallel_jobs(kJobs, threads, [&](std::size_t job, int) {
      deblock_leaves(code, plane, log_scale, r, vertical, count * job / kJobs, count * (job + 1) / kJobs);
    });
}

}  // namespace ifsforge
