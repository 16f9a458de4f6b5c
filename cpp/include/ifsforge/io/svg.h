#pragma once
/// @file SVG of a 2D instance list (seed 6.1.3.5: lines, circles, triangles and squares placed
/// by the vector recursive rendering algorithm).
#include <array>
#include <optional>
#include <string>

#include "ifsforge/vector/instances.h"

namespace ifsforge {

struct SvgOptions {
  int width = 1024;          ///< pixels; the height follows the instances' aspect ratio
  double margin = 0.03;      ///< free border, fraction of the larger side
  std::optional<std::array<float, 3>> background;  ///< none: transparent
  std::string title;         ///< default: the list's name
};

/// @brief Writes one element per instance of positive scale, in list order (later instances on
/// top), atomically: lines as <line>, circles as <circle>, triangles (Eq. 95) and squares as
/// <polygon>; outlines as strokes of width kStrokeWidth d centred on the shape's edges, the
/// same band the other outputs draw. 3D primitives show their outline seen along z: spheres as
/// circles, boxes and cylinders as squares, cones as triangles, tori as rings, meshes as the
/// convex hull of their vertices. Colours are sRGB hex with fill-opacity for alpha < 1.
/// InputError for a 3D list (use draw_instances or the POV-Ray/glTF exporters).
void write_svg(const std::string& path, const InstanceList& instances, const SvgOptions& options = {});

}  // namespace ifsforge
