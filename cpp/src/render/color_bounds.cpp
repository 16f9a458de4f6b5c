#include "ifsforge/render/color_bounds.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"

namespace ifsforge {

Bounds color_bounds(const Ifs& ifs, int levels) {
  if (levels < 0) throw InputError("color bounds need levels >= 0");
  ifs.require_attractor();
  const int k = ifs.spatial_dims(), n = ifs.dim();
  Bounds b{std::vector<double>(n - k, std::numeric_limits<double>::infinity()),
           std::vector<double>(n - k, -std::numeric_limits<double>::infinity())};
  std::vector<Point> level{ifs.start_point()};
  auto widen = [&](const Point& p) {
    for (int c = k; c < n; ++c) {
      b.lo[c - k] = std::min(b.lo[c - k], p[c]);
      b.hi[c - k] = std::max(b.hi[c - k], p[c]);
    }
  };
  widen(level[0]);
  for (int depth = 0; depth < levels && level.size() * ifs.size() <= (1u << 20); ++depth) {
    std::vector<Point> next;
    next.reserve(level.size() * ifs.size());
    for (const Point& p : level)
      for (const AffineMap& m : ifs.maps()) {
        next.push_back(m(p));
        widen(next.back());
      }
    level.swap(next);
  }
  return b;
}

}  // namespace ifsforge
