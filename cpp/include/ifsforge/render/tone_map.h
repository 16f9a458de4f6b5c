#pragma once
/// @file From a raster to a displayable image.
#include <string>

#include "ifsforge/core/image.h"
#include "ifsforge/render/raster.h"

namespace ifsforge {

struct ToneOptions {
  /// "binary" (coverage), "density" (log density), "color" (the colour channels: gray, RGB,
  /// HSI converted to RGB, RGBA), "shaded" (3D systems: the z-buffer lit from the upper left,
  /// times the colour when there is one), or "auto" (shaded for 3D systems, else color when
  /// the raster has colour, else density).
  std::string mode = "auto";
  double gamma = 2.2;   ///< density: v^(1/gamma) after the log
  bool invert = false;  ///< binary and density: dark attractor on white
};

/// @brief binary/density give 1 channel, color gives 1 (gray), 3 (RGB, HSI) or 4 (RGBA).
/// Colour channels not already in [0, 1] are normalised by their range over the covered
/// pixels (Eq. 101).
Image tone_map(const Raster& raster, const ToneOptions& options = {});

/// @brief HSI (h in [0, 1) of a turn, s and i in [0, 1]) to RGB in [0, 1].
void hsi_to_rgb(double h, double s, double i, float* rgb);

}  // namespace ifsforge
