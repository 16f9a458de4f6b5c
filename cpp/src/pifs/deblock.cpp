#include "ifsforge/pifs/deblock.h"

#include <algorithm>
#include <vector>

#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/planes.h"

namespace ifsforge {
namespace {
constexpr std::size_t kJobs = 64;  // leaf chunks per pass
}

void deblock(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& r, int threads) {
  auto scaled = [&](int v) { return log_scale >= 0 ? v << log_scale : v >> -log_scale; };
  // The step δ between the two pixels at an edge is spread as a linear ramp over `w` pixels on
  // each side, w = the scale (at 1× one pixel: a 3:1 blend of the pair), so a magnified decode
  // loses its block edges as the original does.
  const int w = std::max(1, scaled(1));
  std::vector<float> weight(w);
  for (int k = 0; k < w; ++k) weight[k] = 0.5f * float(w - k) / float(w + 1);
  // Every inner edge is the left or top edge of exactly one leaf. The vertical edges go first,
  // then the horizontal ones: the ramps of one direction touch disjoint pixels (cells under 4w
  // are left), so each pass gives the same result in any order, on any number of threads.
  const std::size_t count = plane.leaves.size();
  threads = pass_threads(threads, double(r.width) * r.height);
  for (const bool vertical : {true, false})
    parallel_jobs(kJobs, threads, [&](std::size_t job, int) {
      for (std::size_t i = count * job / kJobs; i < count * (job + 1) / kJobs; ++i) {
        const PifsLeaf& leaf = plane.leaves[i];
        const int n = scaled(1 << leaf.log_size);
        if (n < 4 * w) continue;
        const int x0 = scaled(leaf.x), y0 = scaled(leaf.y);
        if (vertical && x0 >= w)
          for (int v = 0; v < n; ++v) {
            float* p = r.row(y0 + v) + x0;
            const float delta = p[0] - p[-1];
            for (int k = 0; k < w; ++k) {
              p[-1 - k] += delta * weight[k];
              p[k] -= delta * weight[k];
            }
          }
        if (!vertical && y0 >= w)
          for (int u = 0; u < n; ++u) {
            const float delta = r.row(y0)[x0 + u] - r.row(y0 - 1)[x0 + u];
            for (int k = 0; k < w; ++k) {
              r.row(y0 - 1 - k)[x0 + u] += delta * weight[k];
              r.row(y0 + k)[x0 + u] -= delta * weight[k];
            }
          }
      }
    });
}

}  // namespace ifsforge
