#pragma once
/// @file Fractal palettes (seed 6.1.3.3): colour lookup tables whose components are fractal
/// interpolation functions (Eq. 94) through a few colour stops. The vertical scaling factors
/// a22 are the roughness: all 0 gives the piecewise-linear palette, larger |a22| adds
/// self-affine detail of larger amplitude. Components live in RGB, HLS or HSI; the seed's
/// example interpolates HLS lightness only.
#include <array>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/core/image.h"

namespace ifsforge {

enum class ColorSpace { Rgb, Hls, Hsi };
template <>
struct EnumNames<ColorSpace> {
  static constexpr const char* what = "color space";
  static constexpr NamedValue<ColorSpace> values[] = {
      {ColorSpace::Rgb, "rgb"},
      {ColorSpace::Hls, "hls"},
      {ColorSpace::Hsi, "hsi"}};
};

struct PaletteSpec {
  ColorSpace space = ColorSpace::Rgb;
  /// At least 3 colour stops, each in the space's own components: rgb (r, g, b in [0, 1]);
  /// hls (hue in degrees, lightness, saturation in [0, 1]); hsi (hue in degrees, saturation,
  /// intensity in [0, 1]). A hue is interpolated as a plain number (350 -> 370 crosses red)
  /// and taken modulo 360; other components are clamped to [0, 1] after interpolation.
  std::vector<std::array<double, 3>> stops;
  /// Where the stops sit in the table: increasing from 0 to 1. Empty: equally spaced (the
  /// exact O(entries) grid recursion; other positions evaluate each entry by the series).
  std::vector<double> positions;
  /// The roughness of each component: a22 of each map (stops - 1 of them), or one value for
  /// all, |a22| < 1. Empty: 0, a piecewise-linear component.
  std::array<std::vector<double>, 3> a22;
};

/// @brief A colour lookup table: RGB in [0, 1], entry 0 for the lowest input.
struct Palette {
  std::vector<std::array<float, 3>> colors;

  std::size_t size() const { return colors.size(); }
  /// @brief The colour at t in [0, 1] (clamped), linearly between entries.
  std::array<float, 3> lookup(double t) const;
};

/// @brief The palette of `entries` >= 2 colours. InputError names a malformed spec.
Palette make_palette(const PaletteSpec& spec, std::size_t entries);

/// @brief The palette as an RGB image `size()` wide and `rows` high (every row the same):
/// 1 x N strips and N x M textures for image_map, Blender image textures and glTF.
Image palette_image(const Palette& palette, int rows = 1);

/// @brief Colours an image through the palette: its gray level (channel 0 of gray images;
/// Rec. 709 luminance of RGB) picks the colour; an alpha channel is kept. Values in [0, 1].
Image apply_palette(const Image& image, const Palette& palette, int threads = 0);

/// @brief HLS (hue in degrees, lightness and saturation in [0, 1]) to RGB in [0, 1].
void hls_to_rgb(double hue, double lightness, double saturation, float* rgb);

}  // namespace ifsforge
