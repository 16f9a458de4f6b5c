#pragma once
/// @file A raster image of an instance list without POV-Ray: the primitives' triangles
/// projected and painted in order (seed 6.1.3.5's 2D vector IFS as pixels; a quick flat-shaded
/// preview of 3D lists).
#include <array>
#include <optional>

#include "ifsforge/render/frame.h"
#include "ifsforge/core/image.h"
#include "ifsforge/vector/instances.h"

namespace ifsforge {

struct DrawOptions {
  int width = 1024, height = 1024;
  /// The image-plane window; default: the projected bounds of the instances with a 3% margin,
  /// stretched to the image's aspect ratio.
  std::optional<Window> window;
  View view{30.0, 25.0};                           ///< 3D lists: the projection of `ifsforge render --view`
  std::array<float, 4> background{1, 1, 1, 1};    ///< RGBA
  int supersample = 3;                             ///< samples per pixel along each axis (1..8)
  int threads = 0;                                 ///< 0: every core; the image never depends on it
};

/// @brief RGBA image of the instances: 2D lists in list order (later on top), 3D lists far to
/// near along the view, 3D primitives shaded by a light from the upper left, flat ones in their
/// colour; alpha blends. Coverage is box-filtered over supersample^2 samples per pixel.
Image draw_instances(const InstanceList& instances, const DrawOptions& options = {});

}  // namespace ifsforge
