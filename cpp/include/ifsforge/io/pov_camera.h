#pragma once
/// @file A camera, lights and floor framed for a POV-Ray 3.7 scene (z up). The camera's
/// image-plane axes are those of `ifsforge render --view YAW PITCH` (render/frame.h): an
/// orthographic scene renders the same projection, pixel for pixel, seen from above for a
/// positive pitch. The camera vectors are right-handed (right x up points back at the viewer),
/// so the scene shows the IFS's coordinates unmirrored, as Blender does.
#include <array>
#include <vector>

namespace ifsforge {

using PovVector = std::array<double, 3>;

struct PovView {
  double yaw = 30.0, pitch = 25.0;  ///< degrees, as `ifsforge render --view`
  bool orthographic = false;
  double fov = 40.0;                ///< perspective: horizontal field of view in degrees
  double margin = 0.05;             ///< free border on each side, fraction of the image
};

/// POV-Ray checks that direction, right and up are perpendicular; written with float digits
/// they are not quite, so scenes give `sky` and `look_at` after them: POV-Ray then rebuilds the
/// three exactly perpendicular, keeping their lengths and handedness (right = ±|right| sky x
/// direction, up = |up| direction x right), with direction along look_at - location.
struct PovCamera {
  bool orthographic = false;
  PovVector location{}, direction{}, right{}, up{};
  PovVector sky{}, look_at{};  ///< up's direction; the point the camera aims at
};

/// @brief A camera, lights and floor for a scene whose content fills a box.
struct PovFraming {
  PovCamera camera;
  PovVector centre{};       ///< of the box
  double radius = 0.0;      ///< half-diagonal of the box
  PovVector key_light{}, fill_light{};
  double floor_height = 0;  ///< z of a floor plane: under the box, or above it when the camera looks up
};

struct PovBall {
  PovVector centre{};
  double radius = 0.0;
};
/// @brief Frames content known as balls for a width x height image (z up): orthographic
/// windows fit the balls' projections, perspective cameras stand just far enough back for every
/// ball to show whole; centre, radius and floor come from the balls' bounding box.
PovFraming frame_balls(const std::vector<PovBall>& balls, const PovView& view, int width, int height);

}  // namespace ifsforge
