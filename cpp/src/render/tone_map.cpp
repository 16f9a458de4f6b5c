#include "ifsforge/render/tone_map.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

void hsi_to_rgb(double h, double s, double i, float* rgb) {
  // Gonzalez & Woods: the sector of the hue picks which primary is smallest.
  h = h - std::floor(h);
  double angle = h * 2.0 * M_PI;
  const double third = 2.0 * M_PI / 3.0;
  int sector = 0;
  while (angle >= third && sector < 2) {
    angle -= third;
    ++sector;
  }
  const double low = i * (1.0 - s);
  const double high = i * (1.0 + s * std::cos(angle) / std::cos(M_PI / 3.0 - angle));
  const double mid = 3.0 * i - (low + high);
  double r, g, b;
  if (sector == 0) {
    b = low; r = high; g = mid;
  } else if (sector == 1) {
    r = low; g = high; b = mid;
  } else {
    g = low; b = high; r = mid;
  }
  rgb[0] = static_cast<float>(std::clamp(r, 0.0, 1.0));
  rgb[1] = static_cast<float>(std::clamp(g, 0.0, 1.0));
  rgb[2] = static_cast<float>(std::clamp(b, 0.0, 1.0));
}

namespace {

Image density_image(const Raster& raster, const ToneOptions& options, bool binary) {
  Image image(raster.width, raster.height, 1);
  const std::size_t n = raster.density.size();
  double sum = 0.0, peak = 0.0;
  std::size_t covered = 0;
  for (float d : raster.density)
    if (d > 0.0f) {
      sum += d;
      peak = std::max(peak, static_cast<double>(d));
      ++covered;
    }
  const double mean = covered ? sum / covered : 1.0;
  const double top = std::log1p(peak / mean);
  // A log and a power per covered pixel, enough to show in a large render: in row bands on
  // every core (each pixel on its own: the bytes do not depend on the split).
  constexpr std::size_t kBand = 1 << 16;
  parallel_jobs((n + kBand - 1) / kBand, 0, [&](std::size_t band, int) {
    for (std::size_t i = band * kBand, end = std::min(n, i + kBand); i < end; ++i) {
      const double d = raster.density[i];
      double v = 0.0;
      if (d > 0.0) v = binary || top <= 0.0 ? 1.0 : std::pow(std::log1p(d / mean) / top, 1.0 / options.gamma);
      image.pixels[i] = static_cast<float>(options.invert ? 1.0 - v : v);
    }
  });
  return image;
}

Image color_image(const Raster& raster) {
  const int nc = raster.channel_count();
  const std::size_t n = raster.density.size();
  std::vector<double> lo(nc, 0.0), hi(nc, 1.0);
  if (!raster.channels_in_unit_range) {
    // Eq. 101: (value - min) / (max - min), over the pixels the attractor covers.
    lo.assign(nc, INFINITY);
    hi.assign(nc, -INFINITY);
    for (std::size_t i = 0; i < n; ++i)
      if (raster.density[i] > 0.0f)
        for (int c = 0; c < nc; ++c) {
          lo[c] = std::min(lo[c], static_cast<double>(raster.channels[i * nc + c]));
          hi[c] = std::max(hi[c], static_cast<double>(raster.channels[i * nc + c]));
        }
  }
  auto unit = [&](std::size_t i, int c) {
    const double range = hi[c] - lo[c];
    return range > 0 ? std::clamp((raster.channels[i * nc + c] - lo[c]) / range, 0.0, 1.0) : 0.5;
  };
  const ColorModel model = raster.color_model;
  const int out = model == ColorModel::Gray ? 1 : model == ColorModel::Rgba ? 4 : 3;
  Image image(raster.width, raster.height, out);
  // The colour group starts at the first colour channel name.
  int first = 0;
  for (int c = 0; c < nc; ++c) {
    const std::string& name = raster.channel_names[c];
    if (name == "gray" || name == "r" || name == "h") {
      first = c;
      break;
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (raster.density[i] <= 0.0f) continue;
    float* px = &image.pixels[i * out];
    if (model == ColorModel::Hsi) {
      hsi_to_rgb(unit(i, first), unit(i, first + 1), unit(i, first + 2), px);
    } else {
      for (int c = 0; c < out; ++c) px[c] = static_cast<float>(unit(i, first + c));
    }
  }
  return image;
}

/// Lambert shading of the z-buffer: normals from central differences of the (3x3 smoothed)
/// depth in pixel units, light from the upper left and in front.
Image shaded_image(const Raster& raster) {
  const int w = raster.width, h = raster.height;
  const auto covered = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && raster.density[std::size_t(y) * w + x] > 0.0f;
  };
  std::vector<float> depth(raster.depth.size(), 0.0f);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!covered(x, y)) continue;
      double sum = 0.0;
      int n = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (covered(x + dx, y + dy)) {
            sum += raster.depth[std::size_t(y + dy) * w + x + dx];
            ++n;
          }
      depth[std::size_t(y) * w + x] = static_cast<float>(sum / n / raster.pixel_size);
    }
  const Image color = raster.color_model != ColorModel::None ? color_image(raster) : Image();
  const int out = color.channels ? std::min(color.channels, 3) : 1;
  Image image(w, h, out);
  const double light[3] = {-0.45, 0.55, 0.70};  // x right, y down: upper left, towards the viewer
  auto slope = [&](int x, int y, int dx, int dy) {
    const bool a = covered(x - dx, y - dy), b = covered(x + dx, y + dy);
    const float c = depth[std::size_t(y) * w + x];
    if (a && b) return 0.5 * (depth[std::size_t(y + dy) * w + x + dx] - depth[std::size_t(y - dy) * w + x - dx]);
    if (b) return static_cast<double>(depth[std::size_t(y + dy) * w + x + dx] - c);
    if (a) return static_cast<double>(c - depth[std::size_t(y - dy) * w + x - dx]);
    return 0.0;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!covered(x, y)) continue;
      // Depth grows towards the viewer; image y grows downwards.
      const double nx = -slope(x, y, 1, 0), ny = slope(x, y, 0, 1), nz = 1.0;
      const double length = std::sqrt(nx * nx + ny * ny + nz * nz);
      const double lambert = std::max(0.0, (nx * light[0] + ny * light[1] + nz * light[2]) / length);
      const float shade = static_cast<float>(0.2 + 0.8 * lambert);
      const std::size_t i = std::size_t(y) * w + x;
      for (int c = 0; c < out; ++c)
        image.pixels[i * out + c] = shade * (color.channels ? color.pixels[i * color.channels + c] : 1.0f);
    }
  return image;
}

}  // namespace

Image tone_map(const Raster& raster, const ToneOptions& options) {
  std::string mode = options.mode;
  if (mode == "auto") mode = !raster.depth.empty() ? "shaded" : raster.color_model == ColorModel::None ? "density" : "color";
  if (mode == "shaded") {
    if (raster.depth.empty()) throw InputError("shaded images need a 3D system (a z-buffer)");
    return shaded_image(raster);
  }
  if (mode == "binary") return density_image(raster, options, true);
  if (mode == "density") return density_image(raster, options, false);
  if (mode == "color" || mode == "colour") {
    if (raster.color_model == ColorModel::None)
      throw InputError("the image has no color channels; use mode binary or density");
    return color_image(raster);
  }
  throw InputError("unknown tone mode '" + options.mode + "'; choose auto, binary, density, color or shaded");
}

}  // namespace ifsforge
