#pragma once
/// @file POV-Ray 3.7 pieces shared by every exporter that writes scenes (instances, terrains):
/// fast number formatting, a camera and lights framed from a bounding box (pov_camera.cpp),
/// the scene preamble, the ifsforge.inc include, and running the real `povray` headless. Text
/// from input reaches scenes only through io/pov_text.h (included here).
///
/// Scenes keep the coordinates of the IFS unchanged with z up. The camera's image-plane axes
/// are those of `ifsforge render --view YAW PITCH` (render/frame.h): an orthographic scene
/// renders the same projection, pixel for pixel, seen from above for a positive pitch. The
/// camera vectors are right-handed (right x up points back at the viewer), so the scene shows
/// the IFS's coordinates unmirrored, as Blender does.
#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/io/pov_text.h"

namespace ifsforge {

using PovVector = std::array<double, 3>;

/// @brief Writes the shortest text that reads back as `value` (float precision) and returns
/// the end. Needs 16 bytes. Non-finite values are written as 0.
char* pov_number(char* out, float value);
/// @brief Writes "<x,y,z>" (needs 52 bytes).
char* pov_vector(char* out, float x, float y, float z);
/// @brief Writes `value` in [0, 1] with 3 decimals (colours; needs 8 bytes).
char* pov_unit(char* out, float value);

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

/// @brief Frames the box [lo, hi] (z up) for a width x height image: orthographic windows fit
/// the box's projection; perspective cameras aim at its centre from just far enough away for
/// all 8 corners to show. The key light sits above-left behind the camera, the fill light right.
PovFraming frame_box(const PovVector& lo, const PovVector& hi, const PovView& view, int width, int height);

struct PovBall {
  PovVector centre{};
  double radius = 0.0;
};
/// @brief The same for content known as balls (tighter than their bounding box): orthographic
/// windows fit the balls' projections, perspective cameras stand just far enough back for every
/// ball to show whole; centre, radius and floor come from the balls' bounding box.
PovFraming frame_balls(const std::vector<PovBall>& balls, const PovView& view, int width, int height);

enum class PovQuality { Draft, Normal, High };
PovQuality parse_pov_quality(const std::string& text);  ///< "draft", "normal", "high"
const char* to_string(PovQuality q);

/// @brief The surroundings of a scene.
struct PovEnvironment {
  bool floor = true;                          ///< a checkered plane at framing.floor_height
  bool sky = true;                            ///< a sky sphere; otherwise `background`
  std::array<float, 3> background{1, 1, 1};
  PovQuality quality = PovQuality::Normal;    ///< draft: no shadows; high: soft shadows, radiosity
};

/// @brief The preamble of a scene: comments naming `title` (pov_comment) and how to render,
/// #version, #include "ifsforge.inc", IFS_Title (pov_string of `title`), global_settings, the
/// camera (with sky and look_at, see PovCamera), lights, sky or background, floor.
/// `extra_comment` lines go into the header comment (pov_comment_lines).
std::string pov_preamble(const std::string& title, const std::string& extra_comment,
                         const PovFraming& framing, const PovEnvironment& environment, int width, int height);

/// @brief The text of ifsforge.inc; the repository's povray/ifsforge.inc holds the same bytes.
const std::string& povray_include();
/// @brief Writes ifsforge.inc into `folder` (atomically): scenes include it from beside them.
void write_povray_include(const std::string& folder);

/// @brief Writes `size` bytes through `file`; FileError naming `path` when the disk refuses.
void write_bytes(std::FILE* file, const char* data, std::size_t size, const std::string& path);

struct PovRenderOptions {
  int width = 800, height = 600;
  double antialias = 0.3;  ///< POV-Ray's +A threshold; 0 turns antialiasing off
  int threads = 0;         ///< POV-Ray's render threads (+WT); 0: its default (every core)
  ProgressCallback progress;  ///< polled while POV-Ray runs (fraction 0 until done); false kills it
};

/// @brief Renders `scene` with the real POV-Ray 3.7 (`povray` on PATH) into the PNG `image`,
/// headless (+I +O +W +H -D +FN [+A]). POV-Ray runs in the scene's folder (its file-I/O
/// restrictions allow the working directory) and renders to a temporary name there; the image
/// appears atomically. FileError when povray is missing, or with POV-Ray's last messages when it
/// fails; Cancelled when the progress callback says stop.
void render_povray(const std::string& scene, const std::string& image, const PovRenderOptions& options = {});

}  // namespace ifsforge
