#include "ifsforge/pifs/deblock.h"

namespace ifsforge {

void deblock(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsRaster& r) {
  auto scaled = [&](int v) { return log_scale >= 0 ? v << log_scale : v >> -log_scale; };
  // Every inner edge is the left or top edge of exactly one leaf.
  for (const PifsLeaf& leaf : plane.leaves) {
    const int n = scaled(1 << leaf.log_size);
    if (n < 4) continue;
    const int x0 = scaled(leaf.x), y0 = scaled(leaf.y);
    if (x0 > 0)
      for (int v = 0; v < n; ++v) {
        float* p = r.row(y0 + v) + x0;
        const float a = p[-1], b = p[0];
        p[-1] = 0.75f * a + 0.25f * b;
        p[0] = 0.25f * a + 0.75f * b;
      }
    if (y0 > 0) {
      float* above = r.row(y0 - 1) + x0;
      float* below = r.row(y0) + x0;
      for (int u = 0; u < n; ++u) {
        const float a = above[u], b = below[u];
        above[u] = 0.75f * a + 0.25f * b;
        below[u] = 0.25f * a + 0.75f * b;
      }
    }
  }
}

}  // namespace ifsforge
