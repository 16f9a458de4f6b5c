#pragma once
/// @file What a 2D renderer produces: a density (hits or measure) per pixel and the mean of
/// every extra channel (colour, alpha, ...) over the points that fell in the pixel.
#include <string>
#include <vector>

#include "ifsforge/core/pages.h"
#include "ifsforge/model/channel_layout.h"

namespace ifsforge {

struct Raster {
  int width = 0, height = 0;
  /// Hits (random iteration) or mass of the invariant measure (recursive renderers); a
  /// covered pixel is never 0 (a mass that would underflow is stored as the smallest float);
  /// row-major, row 0 at the top. Zero means the attractor misses the pixel.
  LargeVector<float> density;
  /// Names of the extra channels, e.g. {"r", "g", "b"}; empty for a purely spatial system.
  std::vector<std::string> channel_names;
  /// How the extra channels are to be shown.
  ColorModel color_model = ColorModel::None;
  /// True when channel values are already in [0, 1] (e.g. colours stolen from an image);
  /// otherwise tone mapping normalises them by their range (Eq. 101).
  bool channels_in_unit_range = false;
  /// Per pixel, per channel mean: pixel-major (width * height * channels).
  LargeVector<float> channels;
  /// 3D systems: per pixel, the largest depth towards the viewer of the points that fell in it
  /// (a z-buffer; -inf where nothing fell), for shaded views. Empty for 2D systems.
  LargeVector<float> depth;
  /// Width of a pixel in the units of the space (to turn depth differences into slopes).
  double pixel_size = 1.0;
  /// Points plotted (random iteration) or leaves visited (recursive renderers).
  std::uint64_t points = 0;

  int channel_count() const { return static_cast<int>(channel_names.size()); }
  std::size_t covered() const;
};

}  // namespace ifsforge
