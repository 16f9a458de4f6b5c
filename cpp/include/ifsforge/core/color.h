#pragma once
/// @file The one colour rule. Colour channels everywhere in ifsforge are display values:
/// sRGB-encoded, in [0, 1] (after the Eq. 101 normalization). A writer whose reader expects
/// linear light (glTF COLOR_0 and baseColorFactor, the OpenVDB "color" grid that Blender's
/// Principled Volume reads, Blender colour attributes) converts with srgb_to_linear; PNG, PLY
/// vertex colours and POV-Ray `srgb` take the display values as they are.
#include <algorithm>
#include <cmath>
#include <type_traits>

namespace ifsforge {

/// @brief The sRGB decoding (IEC 61966-2-1) of a display value, clamped to [0, 1] first. In the
/// precision of its argument: float for grids and vertex colours (powf is twice as fast as pow,
/// and a .vdb of millions of voxels converts every one), double elsewhere.
template <typename T>
inline T srgb_to_linear(T c) {
  static_assert(std::is_floating_point_v<T>, "srgb_to_linear takes float or double");
  c = std::clamp(c, T(0), T(1));
  return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}

/// @brief The sRGB encoding, inverse of srgb_to_linear on [0, 1].
inline double linear_to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

}  // namespace ifsforge
