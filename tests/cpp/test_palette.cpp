// Fractal palettes (6.1.3.3): piecewise-linear limit, colour stops hit, roughness in one HLS
// component only, application to images, POV-Ray color_map export, refusal of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/io/pov_palette.h"
#include "ifsforge/texture/palette.h"

using namespace ifsforge;

namespace {

PaletteSpec earth(double roughness) {
  PaletteSpec s;
  s.stops = {{0.05, 0.2, 0.45}, {0.85, 0.8, 0.55}, {0.2, 0.55, 0.15}, {0.45, 0.35, 0.2}, {0.95, 0.95, 0.97}};
  s.a22 = {std::vector<double>{roughness, -roughness, roughness, -roughness}, std::vector<double>{roughness},
           std::vector<double>{-roughness}};
  return s;
}

/// RGB to (hue degrees, lightness, saturation), the inverse of hls_to_rgb.
std::array<double, 3> rgb_to_hls(const std::array<float, 3>& c) {
  const double hi = std::max({c[0], c[1], c[2]}), lo = std::min({c[0], c[1], c[2]});
  const double l = 0.5 * (hi + lo);
  if (hi == lo) return {0, l, 0};
  const double d = hi - lo, s = l <= 0.5 ? d / (hi + lo) : d / (2 - hi - lo);
  double h = hi == c[0] ? (c[1] - c[2]) / d : hi == c[1] ? 2 + (c[2] - c[0]) / d : 4 + (c[0] - c[1]) / d;
  h = std::fmod(60 * h + 360, 360);
  return {h, l, s};
}

}  // namespace

TEST(Palette, ZeroRoughnessIsPiecewiseLinear) {
  const PaletteSpec s = earth(0.0);
  const Palette p = make_palette(s, 1001);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double t = 4.0 * i / 1000.0;
    const std::size_t k = std::min<std::size_t>(std::size_t(t), 3);
    for (int c = 0; c < 3; ++c)
      ASSERT_NEAR(p.colors[i][c], s.stops[k][c] + (s.stops[k + 1][c] - s.stops[k][c]) * (t - k), 1e-6) << i;
  }
}

TEST(Palette, HitsEveryStop) {
  const PaletteSpec s = earth(0.6);
  const Palette p = make_palette(s, 4 * 1024 + 1);
  for (int k = 0; k < 5; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(p.colors[1024 * k][c], float(s.stops[k][c])) << k;
  // Unevenly placed stops go through the series evaluation and still hit.
  PaletteSpec uneven = s;
  uneven.positions = {0.0, 0.125, 0.5, 0.75, 1.0};
  const Palette q = make_palette(uneven, 4097);
  for (int k = 0; k < 5; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(q.colors[std::size_t(uneven.positions[k] * 4096)][c], float(s.stops[k][c]));
}

TEST(Palette, RoughnessAddsDetail) {
  // Total variation of the green channel grows with |a22| (more, larger wiggles).
  double previous = 0;
  for (double r : {0.0, 0.3, 0.5, 0.7}) {
    const Palette p = make_palette(earth(r), 4096);
    double variation = 0;
    for (std::size_t i = 1; i < p.size(); ++i) variation += std::fabs(p.colors[i][1] - p.colors[i - 1][1]);
    EXPECT_GT(variation, previous) << r;
    previous = variation;
  }
}

TEST(Palette, LightnessOnlyInHls) {
  // The seed's example: interpolate HLS lightness fractally, hue and saturation linearly.
  PaletteSpec s;
  s.space = ColorSpace::Hls;
  s.stops = {{20, 0.25, 0.6}, {35, 0.55, 0.6}, {50, 0.4, 0.6}, {40, 0.7, 0.6}};
  s.a22[1] = {0.55, -0.5, 0.6};
  const Palette p = make_palette(s, 3 * 100 + 1);
  double rough = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double t = 3.0 * i / 300.0;
    const std::size_t k = std::min<std::size_t>(std::size_t(t), 2);
    const auto hls = rgb_to_hls(p.colors[i]);
    EXPECT_NEAR(hls[0], s.stops[k][0] + (s.stops[k + 1][0] - s.stops[k][0]) * (t - k), 0.05) << i;
    EXPECT_NEAR(hls[2], 0.6, 1e-4) << i;
    rough = std::max(rough, std::fabs(hls[1] - (s.stops[k][1] + (s.stops[k + 1][1] - s.stops[k][1]) * (t - k))));
  }
  EXPECT_GT(rough, 0.05);  // the lightness is not the linear one
  float rgb[3];
  hls_to_rgb(0, 0.5, 1, rgb);
  EXPECT_EQ(std::vector<float>(rgb, rgb + 3), (std::vector<float>{1, 0, 0}));
  hls_to_rgb(240, 0.25, 1, rgb);
  EXPECT_EQ(std::vector<float>(rgb, rgb + 3), (std::vector<float>{0, 0, 0.5f}));
  hls_to_rgb(77, 0.3, 0, rgb);
  EXPECT_EQ(std::vector<float>(rgb, rgb + 3), (std::vector<float>{0.3f, 0.3f, 0.3f}));
}

TEST(Palette, AppliesToImagesAndExportsToPovRay) {
  const Palette p = make_palette(earth(0.4), 256);
  Image gray(3, 1, 2);
  gray.at(0, 0, 0) = 0.0f, gray.at(1, 0, 0) = 1.0f, gray.at(2, 0, 0) = 128.0f / 255.0f;
  gray.at(0, 0, 1) = 0.25f, gray.at(1, 0, 1) = 0.5f, gray.at(2, 0, 1) = 1.0f;
  const Image out = apply_palette(gray, p);
  ASSERT_EQ(out.channels, 4);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(out.at(0, 0, c), p.colors.front()[c]);
    EXPECT_EQ(out.at(1, 0, c), p.colors.back()[c]);
    EXPECT_NEAR(out.at(2, 0, c), p.colors[128][c], 1e-6);
  }
  EXPECT_EQ(out.at(0, 0, 3), 0.25f);
  EXPECT_EQ(palette_image(p, 4).width, 256);
  EXPECT_EQ(palette_image(p, 4).height, 4);

  const Palette big = make_palette(earth(0.4), 4096);
  const std::string map = pov_color_map(big);
  EXPECT_EQ(std::count(map.begin(), map.end(), '['), 256);  // POV-Ray's limit
  EXPECT_EQ(map.rfind("color_map {", 0), 0u);
  std::ostringstream first;
  first.precision(6);
  char expected[96];
  std::snprintf(expected, sizeof expected, "[0.000000 srgb <%.6f, %.6f, %.6f>]", big.colors[0][0], big.colors[0][1],
                big.colors[0][2]);
  EXPECT_NE(map.find(expected), std::string::npos) << map.substr(0, 200);
  std::snprintf(expected, sizeof expected, "[1.000000 srgb <%.6f, %.6f, %.6f>]", big.colors.back()[0],
                big.colors.back()[1], big.colors.back()[2]);
  EXPECT_NE(map.find(expected), std::string::npos);
}

TEST(Palette, RefusesBadInput) {
  PaletteSpec s = earth(0.3);
  EXPECT_THROW(make_palette(s, 1), InputError);
  PaletteSpec two = s;
  two.stops.resize(2);
  two.a22 = {};
  EXPECT_THROW(make_palette(two, 16), InputError);
  PaletteSpec steep = s;
  steep.a22[0] = {0.2, 1.2, 0.1, 0.1};
  EXPECT_THROW(make_palette(steep, 16), InputError);
  PaletteSpec unsorted = s;
  unsorted.positions = {0, 0.5, 0.4, 0.8, 1};
  EXPECT_THROW(make_palette(unsorted, 16), InputError);
  PaletteSpec short_range = s;
  short_range.positions = {0, 0.2, 0.4, 0.8, 0.9};
  EXPECT_THROW(make_palette(short_range, 16), InputError);
  EXPECT_THROW(parse_name<ColorSpace>("cmyk"), InputError);
}
