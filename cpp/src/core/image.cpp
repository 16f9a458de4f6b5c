#include "ifsforge/core/image.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/pages.h"

namespace ifsforge {

Image::Image(int w, int h, int c) : width(w), height(h), channels(c) {
  // Every image of the core is allocated here: its size is checked against the budget before
  // a byte is touched, whatever made the request (a reader, a decoder, a palette, a renderer).
  if (w < 0 || h < 0 || c < 0) throw InputError("an image cannot have a negative size");
  check_memory(4.0 * w * h * c, "a " + std::to_string(w) + "x" + std::to_string(h) + " image of " +
                                    std::to_string(c) + " channel(s)");
  resize_large(pixels, std::size_t(w) * h * c);
}

void Image::sample(double x, double y, float* out) const {
  // Pixel centres sit at half-integers.
  x = std::clamp(x - 0.5, 0.0, static_cast<double>(width - 1));
  y = std::clamp(y - 0.5, 0.0, static_cast<double>(height - 1));
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const int x1 = std::min(x0 + 1, width - 1), y1 = std::min(y0 + 1, height - 1);
  const float fx = static_cast<float>(x - x0), fy = static_cast<float>(y - y0);
  for (int c = 0; c < channels; ++c) {
    const float top = at(x0, y0, c) * (1 - fx) + at(x1, y0, c) * fx;
    const float bottom = at(x0, y1, c) * (1 - fx) + at(x1, y1, c) * fx;
    out[c] = top * (1 - fy) + bottom * fy;
  }
}

}  // namespace ifsforge
