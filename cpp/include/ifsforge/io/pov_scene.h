#pragma once
/// @file The text of POV-Ray 3.7 scenes shared by every exporter (instances, terrains): fast
/// number formatting, the scene preamble and the ifsforge.inc include (embedded at build time
/// from povray/ifsforge.inc). Scenes keep the coordinates of the IFS unchanged with z up. Text
/// from input reaches scenes only through io/pov_text.h (included here).
#include <array>
#include <string>

#include "ifsforge/core/names.h"
#include "ifsforge/io/pov_camera.h"
#include "ifsforge/io/pov_text.h"

namespace ifsforge {

/// @brief Writes the shortest text that reads back as `value` (float precision) and returns
/// the end. Needs 16 bytes. Non-finite values are written as 0.
char* pov_number(char* out, float value);
/// @brief Writes "<x,y,z>" (needs 52 bytes).
char* pov_vector(char* out, float x, float y, float z);
/// @brief Writes `value` in [0, 1] with 3 decimals (colours; needs 8 bytes).
char* pov_unit(char* out, float value);

enum class PovQuality { Draft, Normal, High };
template <>
struct EnumNames<PovQuality> {
  static constexpr const char* what = "POV-Ray quality";
  static constexpr NamedValue<PovQuality> values[] = {
      {PovQuality::Draft, "draft"},
      {PovQuality::Normal, "normal"},
      {PovQuality::High, "high"}};
};

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

}  // namespace ifsforge
