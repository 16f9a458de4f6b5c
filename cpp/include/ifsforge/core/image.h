#pragma once
/// @file A plain image: interleaved float channels in [0, 1], row 0 at the top.
#include <vector>

#include "ifsforge/core/pages.h"

namespace ifsforge {

/// @brief The largest side of any image ifsforge makes or reads back (PNG's practical limit).
constexpr int kMaxImageSide = 65535;

struct Image {
  int width = 0, height = 0, channels = 0;  ///< 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA
  LargeVector<float> pixels;

  Image() = default;
  /// @brief A black image (large ones on huge pages: fewer first-touch faults).
  Image(int w, int h, int c);
  float& at(int x, int y, int c) { return pixels[(std::size_t(y) * width + x) * channels + c]; }
  float at(int x, int y, int c) const { return pixels[(std::size_t(y) * width + x) * channels + c]; }
  /// @brief Bilinear sample at continuous pixel coordinates (clamped to the edges).
  void sample(double x, double y, float* out) const;
};

}  // namespace ifsforge
