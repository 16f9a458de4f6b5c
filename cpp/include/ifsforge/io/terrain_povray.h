#pragma once
/// @file A terrain as a POV-Ray 3.7 scene: a height_field (reading a 16-bit PNG) or a mesh2,
/// coloured by height through the palette as a color_map.
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/terrain/terrain.h"
#include "ifsforge/texture/palette.h"

namespace ifsforge {

/// HeightField: the scene reads `<scene stem>_height.png` (written beside it, 16 bit);
/// Mesh2: the triangles are inlined (any grid without resampling; large files).
enum class TerrainPovShape { HeightField, Mesh2 };
template <>
struct EnumNames<TerrainPovShape> {
  static constexpr const char* what = "POV-Ray terrain shape";
  static constexpr NamedValue<TerrainPovShape> values[] = {
      {TerrainPovShape::HeightField, "height_field"}, {TerrainPovShape::Mesh2, "mesh2"}};
};

/// Perspective: from the south-west, 35° above the horizon; Top: orthographic, straight down,
/// north up, framing exactly the outline (render at the outline's aspect ratio).
enum class TerrainPovCamera { Perspective, Top };
template <>
struct EnumNames<TerrainPovCamera> {
  static constexpr const char* what = "POV-Ray terrain camera";
  static constexpr NamedValue<TerrainPovCamera> values[] = {
      {TerrainPovCamera::Perspective, "perspective"}, {TerrainPovCamera::Top, "top"}};
};

struct TerrainPovOptions {
  TerrainPovShape shape = TerrainPovShape::HeightField;
  TerrainPovCamera camera = TerrainPovCamera::Perspective;
  /// No lights: every point shows its palette colour unshaded (maps, and tests against
  /// apply_palette); otherwise a sun and a sky.
  bool flat = false;
  /// The render's width / height, for the perspective camera.
  double aspect = 4.0 / 3.0;
  /// First comment line and IFS_Title (pov_comment, pov_string).
  std::string title = "ifsforge terrain";
  /// The palette's name: the colours are declared as IFS_Palette_<name> (pov_identifier).
  std::string palette_name = "terrain";
};

/// @brief Writes the scene (atomically) and, for a height_field, its PNG; returns the paths
/// written (a height_field's PNG is `<scene stem>_height.png`, the stem reduced to ASCII
/// letters, digits, '.', '-' and '_'). The palette (empty: a gray ramp) becomes a `gradient y` pigment spanning the
/// terrain's heights. POV-Ray axes: x east, y up, z north (POV-Ray's own y-up convention,
/// which height_field uses natively). Render from the scene's folder (the PNG is named
/// relative to it), e.g. with render_povray (io/povray.h) or
/// `povray +Iscene.pov +Oscene.png +W800 +H600 +A`.
std::vector<std::string> write_terrain_pov(const std::string& path, const Terrain& terrain, const Palette& palette,
                                           const TerrainPovOptions& options = {}, int threads = 0);

}  // namespace ifsforge
