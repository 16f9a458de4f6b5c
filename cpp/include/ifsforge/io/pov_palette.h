#pragma once
/// @file A fractal palette as POV-Ray text: a color_map and an include declaring it.
#include <cstddef>
#include <string>

#include "ifsforge/texture/palette.h"

namespace ifsforge {

/// @brief A POV-Ray `color_map { ... }` with at most 256 entries (POV-Ray's limit), colours
/// given as `srgb` so that a render with assumed_gamma 1.0 shows the palette's values. With
/// `linear`, as `rgb` of the sRGB-decoded values instead: the same colours under assumed_gamma
/// 1.0 (POV-Ray 3.7's default), and parsed even before any assumed_gamma is set, which `srgb`
/// refuses ("Cannot parse sRGB colors before assumed_gamma has been set").
std::string pov_color_map(const Palette& palette, std::size_t entries = 256, bool linear = false);

/// @brief A POV-Ray include declaring the palette: comment lines naming it (pov_comment) and
/// `about`, then `#declare IFS_Palette_<name> = color_map {...}` (pov_identifier) with linear
/// colours, so it parses wherever a scene includes it, with or without assumed_gamma.
std::string pov_palette_include(const Palette& palette, const std::string& name, const std::string& about = "",
                                std::size_t entries = 256);

}  // namespace ifsforge
