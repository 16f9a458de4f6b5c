#include "ifsforge/render/box_counting.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"

namespace ifsforge {

BoxCounting box_counting(const std::vector<std::uint8_t>& mask, int width, int height, int min_box,
                         int max_box) {
  if (mask.size() != std::size_t(width) * height) throw InputError("mask size does not match");
  if (max_box <= 0) {
    // Boxes up to 1/32 of the covered extent: larger ones see the set as a blob or a line
    // and bend the slope (the Koch curve at 1/8 of its length is one straight row of boxes).
    int x0 = width, x1 = -1, y0 = height, y1 = -1;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        if (mask[std::size_t(y) * width + x]) {
          x0 = std::min(x0, x);
          x1 = std::max(x1, x);
          y0 = std::min(y0, y);
          y1 = std::max(y1, y);
        }
    const int extent = std::max(x1 - x0, y1 - y0) + 1;
    max_box = std::max(2 * min_box, extent / 32);
  }
  if (min_box < 1 || max_box < min_box) throw InputError("need 1 <= min_box <= max_box");
  BoxCounting result;
  // Each level ORs 2x2 blocks of the previous one.
  std::vector<std::uint8_t> level = mask;
  int w = width, h = height, size = 1;
  while (size <= max_box) {
    if (size >= min_box) {
      std::uint64_t count = 0;
      for (std::uint8_t v : level) count += v != 0;
      result.box_sizes.push_back(size);
      result.box_counts.push_back(count);
    }
    const int nw = (w + 1) / 2, nh = (h + 1) / 2;
    std::vector<std::uint8_t> next(std::size_t(nw) * nh, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (level[std::size_t(y) * w + x]) next[std::size_t(y / 2) * nw + x / 2] = 1;
    level.swap(next);
    w = nw;
    h = nh;
    size *= 2;
  }
  // A slope through two or three sizes is mostly the pixel grid's: a set spanning a few hundred
  // pixels reads 1.15 for a dimension of 1.46. Fewer than four sizes is refused, with what would do.
  const std::size_t n = result.box_sizes.size();
  if (n < kMinBoxSizes)
    throw InputError("box counting needs at least " + std::to_string(kMinBoxSizes) + " box sizes (" +
                     std::to_string(min_box) + " to " + std::to_string(min_box << (kMinBoxSizes - 1)) +
                     " pixels), but boxes above " + std::to_string(max_box) +
                     " pixels (1/32 of the set's extent) bend the slope: render the set at least " +
                     std::to_string(32 * (min_box << (kMinBoxSizes - 1))) + " pixels across");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = -std::log(static_cast<double>(result.box_sizes[i]));
    const double y = std::log(static_cast<double>(std::max<std::uint64_t>(1, result.box_counts[i])));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  result.dimension = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return result;
}

BoxCounting box_counting(const Raster& raster, int min_box, int max_box) {
  std::vector<std::uint8_t> mask(raster.density.size());
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = raster.density[i] > 0.0f;
  return box_counting(mask, raster.width, raster.height, min_box, max_box);
}

}  // namespace ifsforge
