#include "ifsforge/volume/volume.h"

#include <algorithm>

#include "ifsforge/core/error.h"
#include "ifsforge/render/tone_map.h"

namespace ifsforge {

std::size_t Volume::find(std::uint64_t key) const {
  const auto it = std::lower_bound(keys.begin(), keys.end(), key);
  return it != keys.end() && *it == key ? static_cast<std::size_t>(it - keys.begin()) : keys.size();
}

void AttributeRecipe::evaluate(const float* channels, float* out) const {
  auto unit = [&](int c) { return static_cast<float>(std::clamp(scale[c] * channels[c] + offset[c], 0.0, 1.0)); };
  switch (source) {
    case Source::Rgb:
      for (int c = 0; c < 3; ++c) out[c] = unit(first + c);
      break;
    case Source::Hsi: hsi_to_rgb(unit(first), unit(first + 1), unit(first + 2), out); break;
    case Source::GrayAsRgb: std::fill_n(out, 3, unit(first)); break;
    case Source::Channel: out[0] = unit(first); break;
  }
}

std::vector<AttributeRecipe> attribute_recipes(const Volume& volume, ColorScale scale) {
  const int nc = volume.channel_count();
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
  auto channel = [&](const std::string& name) {
    const auto it = std::find(volume.channel_names.begin(), volume.channel_names.end(), name);
    return it == volume.channel_names.end() ? -1 : static_cast<int>(it - volume.channel_names.begin());
  };
  auto recipe = [&](std::string name, AttributeRecipe::Source source, int first) {
    return AttributeRecipe{std::move(name), source == AttributeRecipe::Source::Channel ? 1 : 3, source, first, a, b};
  };

  std::vector<AttributeRecipe> out;
  std::vector<bool> used(nc, false);
  const ColorModel model = volume.color_model;
  if (model == ColorModel::Gray) {
    // Gray also gets its own grid below, so it is not marked used.
    out.push_back(recipe("color", AttributeRecipe::Source::GrayAsRgb, channel("gray")));
  } else if (model == ColorModel::Rgb || model == ColorModel::Rgba || model == ColorModel::Hsi) {
    const bool hsi = model == ColorModel::Hsi;
    const int first = channel(hsi ? "h" : "r");
    out.push_back(recipe("color", hsi ? AttributeRecipe::Source::Hsi : AttributeRecipe::Source::Rgb, first));
    for (int c = 0; c < 3; ++c) used[first + c] = true;
  }
  for (int c = 0; c < nc; ++c)
    if (!used[c]) out.push_back(recipe(volume.channel_names[c], AttributeRecipe::Source::Channel, c));
  return out;
}

std::vector<VolumeAttribute> volume_attributes(const Volume& volume, ColorScale scale) {
  const int nc = volume.channel_count();
  std::vector<VolumeAttribute> out;
  for (const AttributeRecipe& recipe : attribute_recipes(volume, scale)) {
    VolumeAttribute attribute{recipe.name, recipe.components, std::vector<float>(volume.size() * recipe.components)};
    for (std::size_t v = 0; v < volume.size(); ++v)
      recipe.evaluate(&volume.channels[v * nc], &attribute.values[v * recipe.components]);
    out.push_back(std::move(attribute));
  }
  return out;
}

std::size_t volume_bands(const VoxelGrid& grid) {
  return (static_cast<std::size_t>(grid.dims[0]) + kVolumeBandRows - 1) / kVolumeBandRows;
}

VolumeBandLoader band_loader(const Volume& volume) {
  return [&volume](std::size_t band, bool, Volume&) {
    auto at = [&](std::uint64_t x) {
      return static_cast<std::size_t>(std::lower_bound(volume.keys.begin(), volume.keys.end(), VoxelGrid::key(x, 0, 0)) -
                                      volume.keys.begin());
    };
    const std::size_t first = at(band * kVolumeBandRows), last = at((band + 1) * kVolumeBandRows);
    const std::size_t nc = static_cast<std::size_t>(volume.channel_count());
    return VoxelSpan{volume.keys.data() + first, volume.density.data() + first, volume.channels.data() + first * nc,
                     last - first};
  };
}

}  // namespace ifsforge
