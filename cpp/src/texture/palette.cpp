#include "ifsforge/texture/palette.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/tone_map.h"
#include "ifsforge/interpolation/fractal_interpolation.h"
#include "ifsforge/interpolation/grid_recursion.h"
#include "ifsforge/interpolation/vertical_scaling.h"

namespace ifsforge {

void hls_to_rgb(double hue, double lightness, double saturation, float* rgb) {
  const double h = hue / 360.0 - std::floor(hue / 360.0);
  const double l = std::clamp(lightness, 0.0, 1.0), s = std::clamp(saturation, 0.0, 1.0);
  const double m2 = l <= 0.5 ? l * (1.0 + s) : l + s - l * s, m1 = 2.0 * l - m2;
  auto channel = [&](double x) {
    x -= std::floor(x);
    if (x < 1.0 / 6.0) return m1 + (m2 - m1) * x * 6.0;
    if (x < 0.5) return m2;
    if (x < 2.0 / 3.0) return m1 + (m2 - m1) * (2.0 / 3.0 - x) * 6.0;
    return m1;
  };
  rgb[0] = float(std::clamp(channel(h + 1.0 / 3.0), 0.0, 1.0));
  rgb[1] = float(std::clamp(channel(h), 0.0, 1.0));
  rgb[2] = float(std::clamp(channel(h - 1.0 / 3.0), 0.0, 1.0));
}

std::array<float, 3> Palette::lookup(double t) const {
  if (colors.empty()) throw InputError("the palette is empty");
  if (colors.size() == 1 || !(t > 0.0)) return colors.front();
  const double p = std::min(t, 1.0) * double(colors.size() - 1);
  const std::size_t i = std::min<std::size_t>(std::size_t(p), colors.size() - 2);
  const float f = float(p - double(i));
  std::array<float, 3> out;
  for (int c = 0; c < 3; ++c) out[c] = colors[i][c] + (colors[i + 1][c] - colors[i][c]) * f;
  return out;
}

Palette make_palette(const PaletteSpec& spec, std::size_t entries) {
  const std::size_t stops = spec.stops.size();
  if (stops < 3)
    throw InputError("a fractal palette needs at least 3 color stops (2 interpolation maps), got " +
                     std::to_string(stops));
  if (entries < 2 || entries > (std::size_t(1) << 24))
    throw InputError("a palette has 2 to 16777216 entries, got " + std::to_string(entries));
  for (std::size_t k = 0; k < stops; ++k)
    for (double v : spec.stops[k])
      if (!std::isfinite(v)) throw InputError("palette stop " + std::to_string(k) + " is not finite");
  std::vector<double> positions = spec.positions;
  if (!positions.empty()) {
    if (positions.size() != stops)
      throw InputError("the palette has " + std::to_string(stops) + " stops but " + std::to_string(positions.size()) +
                       " positions");
    if (positions.front() != 0.0 || positions.back() != 1.0)
      throw InputError("palette positions run from 0 to 1");
  } else {
    for (std::size_t k = 0; k < stops; ++k) positions.push_back(double(k) / double(stops - 1));
  }
  check_memory(double(entries) * 40.0, "a palette of " + std::to_string(entries) + " entries");

  std::array<std::vector<double>, 3> component;
  const char* names[3][3] = {{"red", "green", "blue"}, {"hue", "lightness", "saturation"},
                             {"hue", "saturation", "intensity"}};
  std::unique_ptr<GridRecursion> plan;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> values(stops);
    for (std::size_t k = 0; k < stops; ++k) values[k] = spec.stops[k][c];
    std::vector<double> a22 = spec.a22[c].empty() ? std::vector<double>{0.0} : spec.a22[c];
    const std::string what = std::string("palette ") + names[int(spec.space)][c] + " roughness";
    if (a22.size() != 1 && a22.size() != stops - 1)
      throw InputError(what + ": " + std::to_string(stops) + " stops need " + std::to_string(stops - 1) +
                       " factors (one per map) or one for all, got " + std::to_string(a22.size()));
    // Validates the positions and the factors (Eq. 90: increasing x, |a22| < 1).
    FractalInterpolation fif(positions, values, a22);
    if (fif.equally_spaced()) {
      if (!plan) plan = std::make_unique<GridRecursion>(stops - 1, entries);
      component[c].resize(entries);
      plan->evaluate(values.data(), fif.vertical_scaling().data(), component[c].data());
    } else {
      component[c] = fif.sample(entries);
    }
  }
  Palette palette;
  palette.colors.resize(entries);
  for (std::size_t i = 0; i < entries; ++i) {
    float* rgb = palette.colors[i].data();
    const double a = component[0][i], b = component[1][i], c = component[2][i];
    switch (spec.space) {
      case ColorSpace::Rgb:
        rgb[0] = float(std::clamp(a, 0.0, 1.0));
        rgb[1] = float(std::clamp(b, 0.0, 1.0));
        rgb[2] = float(std::clamp(c, 0.0, 1.0));
        break;
      case ColorSpace::Hls:
        hls_to_rgb(a, b, c, rgb);
        break;
      case ColorSpace::Hsi:
        hsi_to_rgb(a / 360.0, std::clamp(b, 0.0, 1.0), std::clamp(c, 0.0, 1.0), rgb);
        break;
    }
  }
  return palette;
}

Image palette_image(const Palette& palette, int rows) {
  if (palette.colors.empty()) throw InputError("the palette is empty");
  if (rows < 1 || rows > 65535) throw InputError("a palette image has 1 to 65535 rows, got " + std::to_string(rows));
  Image image(int(palette.size()), rows, 3);
  for (int y = 0; y < rows; ++y)
    for (std::size_t x = 0; x < palette.size(); ++x)
      for (int c = 0; c < 3; ++c) image.at(int(x), y, c) = palette.colors[x][c];
  return image;
}

Image apply_palette(const Image& image, const Palette& palette, int threads) {
  if (palette.colors.empty()) throw InputError("the palette is empty");
  if (image.width < 1 || image.height < 1 || image.channels < 1 || image.channels > 4)
    throw InputError("apply palette: expected a gray, gray+alpha, RGB or RGBA image");
  const bool alpha = image.channels == 2 || image.channels == 4;
  Image out(image.width, image.height, alpha ? 4 : 3);
  const std::size_t pixels = std::size_t(image.width) * image.height, block = 1 << 16;
  parallel_jobs((pixels + block - 1) / block, threads, [&](std::size_t job, int) {
    for (std::size_t i = job * block; i < std::min(pixels, (job + 1) * block); ++i) {
      const float* p = image.pixels.data() + i * image.channels;
      const double gray = image.channels >= 3 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : p[0];
      const std::array<float, 3> rgb = palette.lookup(gray);
      float* q = out.pixels.data() + i * out.channels;
      q[0] = rgb[0], q[1] = rgb[1], q[2] = rgb[2];
      if (alpha) q[3] = p[image.channels - 1];
    }
  });
  return out;
}

}  // namespace ifsforge
