#include "ifsforge/volume/volume.h"

#include <algorithm>

#include "ifsforge/core/error.h"
#include "ifsforge/render/tone_map.h"

namespace ifsforge {

const char* to_string(VolumeDensity d) {
  switch (d) {
    case VolumeDensity::Binary: return "binary";
    case VolumeDensity::Hits: return "hits";
    case VolumeDensity::Measure: return "measure";
  }
  return "?";
}

VolumeDensity volume_density_from_string(const std::string& name) {
  if (name == "binary") return VolumeDensity::Binary;
  if (name == "hits") return VolumeDensity::Hits;
  if (name == "measure") return VolumeDensity::Measure;
  throw InputError("unknown density '" + name + "'; choose one of: binary, hits, measure");
}

ColorScale color_scale_from_string(const std::string& name) {
  if (name == "auto") return ColorScale::Auto;
  if (name == "range") return ColorScale::Range;
  if (name == "clamp") return ColorScale::Clamp;
  throw InputError("unknown colour scale '" + name + "'; choose one of: auto, range, clamp");
}

std::size_t Volume::find(std::uint64_t key) const {
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return it != keys.end() && *it == key ? static_cast<std::size_t>(it - keys.begin()) : keys.size();
}

std::vector<VolumeAttribute> volume_attributes(const Volume& volume, ColorScale scale) {
  const int nc = volume.channel_count();
  const std::size_t n = volume.size();
  // Per channel v -> a * v + b, then clamped to [0, 1].
  std::vector<double> a(nc, 1.0), b(nc, 0.0);
  for (int c = 0; c < nc; ++c) {
    const double lo = volume.channel_lo[c], hi = volume.channel_hi[c];
    const bool inside = lo >= -1e-9 && hi <= 1.0 + 1e-9;
    const bool range = scale == ColorScale::Range || (scale == ColorScale::Auto && !inside);
    if (range && hi > lo) {
      a[c] = 1.0 / (hi - lo);  // Eq. 101
      b[c] = -lo / (hi - lo);
    }
  }
  auto unit = [&](std::size_t v, int c) {
    return static_cast<float>(std::clamp(a[c] * volume.channels[v * nc + c] + b[c], 0.0, 1.0));
  };
  auto channel = [&](const std::string& name) {
    const auto it = std::find(volume.channel_names.begin(), volume.channel_names.end(), name);
    return it == volume.channel_names.end() ? -1 : static_cast<int>(it - volume.channel_names.begin());
  };

  std::vector<VolumeAttribute> out;
  std::vector<bool> used(nc, false);
  const ColorModel model = volume.color_model;
  if (model == ColorModel::Rgb || model == ColorModel::Rgba || model == ColorModel::Hsi ||
      model == ColorModel::Gray) {
    VolumeAttribute color{"color", 3, std::vector<float>(n * 3)};
    if (model == ColorModel::Gray) {
      const int g = channel("gray");
      for (std::size_t v = 0; v < n; ++v) std::fill_n(&color.values[v * 3], 3, unit(v, g));
      // Gray also gets its own grid below, so it is not marked used.
    } else {
      const bool hsi = model == ColorModel::Hsi;
      const int first = channel(hsi ? "h" : "r");
      for (std::size_t v = 0; v < n; ++v) {
        float* rgb = &color.values[v * 3];
        if (hsi)
          hsi_to_rgb(unit(v, first), unit(v, first + 1), unit(v, first + 2), rgb);
        else
          for (int c = 0; c < 3; ++c) rgb[c] = unit(v, first + c);
      }
      for (int c = 0; c < 3; ++c) used[first + c] = true;
    }
    out.push_back(std::move(color));
  }
  for (int c = 0; c < nc; ++c) {
    if (used[c]) continue;
    VolumeAttribute single{volume.channel_names[c], 1, std::vector<float>(n)};
    for (std::size_t v = 0; v < n; ++v) single.values[v] = unit(v, c);
    out.push_back(std::move(single));
  }
  return out;
}

}  // namespace ifsforge
