#pragma once
/// @file What a volumetric renderer produces: the occupied voxels of a sparse grid, a density
/// per voxel and the mean of every extra channel (colour, gray, alpha, ...) over the points
/// that landed in it (seed 6.2.3.2, 6.3, 6.5.3.1).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/model/channel_layout.h"
#include "ifsforge/volume/voxel_grid.h"

namespace ifsforge {

/// @brief What the density grid holds: 1 per occupied voxel, the number of points (leaves,
/// random points, source voxels) that landed in it, or its share of the invariant measure.
enum class VolumeDensity { Binary, Hits, Measure };
template <>
struct EnumNames<VolumeDensity> {
  static constexpr const char* what = "density";
  static constexpr NamedValue<VolumeDensity> values[] = {
      {VolumeDensity::Binary, "binary"},
      {VolumeDensity::Hits, "hits"},
      {VolumeDensity::Measure, "measure"}};
};

/// @brief How channel values become [0, 1] for output. Auto: values are kept (clamped) when the
/// attractor's range of the channel lies inside [0, 1], else Range. Range: Eq. 101,
/// (v - min) / (max - min) over the attractor's range. Clamp: values clamped to [0, 1].
enum class ColorScale { Auto, Range, Clamp };
template <>
struct EnumNames<ColorScale> {
  static constexpr const char* what = "color scale";
  static constexpr NamedValue<ColorScale> values[] = {
      {ColorScale::Auto, "auto"},
      {ColorScale::Range, "range"},
      {ColorScale::Clamp, "clamp"}};
};

/// A sparse volume: only occupied voxels are stored, sorted by key (x, then y, then z).
struct Volume {
  VoxelGrid grid;
  std::vector<std::uint64_t> keys;   ///< VoxelGrid::key of each occupied voxel, ascending
  std::vector<float> density;        ///< one per voxel (> 0)
  VolumeDensity density_mode = VolumeDensity::Binary;
  /// Names of the extra channels, e.g. {"r", "g", "b"}; empty for a purely spatial system.
  std::vector<std::string> channel_names;
  ColorModel color_model = ColorModel::None;
  /// Per voxel, per channel mean (voxel-major, keys.size() * channel_count()), in the units
  /// of the system.
  std::vector<float> channels;
  /// The attractor's range of each channel (for Eq. 101).
  std::vector<double> channel_lo, channel_hi;
  std::string algorithm;     ///< the renderer that made it
  int depth = 0;             ///< recursion depth (PRR), rewriting levels (DIA), escape bound (ETA)
  std::uint64_t points = 0;  ///< leaves visited, random points plotted, voxels tested

  std::size_t size() const { return keys.size(); }
  int channel_count() const { return static_cast<int>(channel_names.size()); }
  /// @brief Index of the voxel with `key`, or size() when it is not occupied.
  std::size_t find(std::uint64_t key) const;
};

/// The voxels of one band of a volume given band by band: x in [band, band + 1) *
/// kVolumeBandRows, keys ascending, with their density and channel means (voxel-major; both
/// may be null when only keys were asked for).
struct VoxelSpan {
  const std::uint64_t* keys = nullptr;
  const float* density = nullptr;
  const float* channels = nullptr;
  std::size_t size = 0;
};
/// Rows of x per band: the span of a .vdb tree's lower internal nodes, so that a band's leaves
/// are written without any other band's.
constexpr int kVolumeBandRows = 128;
/// Band `band` of a volume: its voxels put in `scratch` (which the caller keeps per thread) or
/// wherever the loader already holds them, ascending. With `keys_only`, the keys alone, and they
/// may come as a merge's inputs: grouped by 8 rows of x (a group never split), in any order
/// within a group and repeated. Called twice per band (keys, then all), from several threads.
using VolumeBandLoader = std::function<VoxelSpan(std::size_t band, bool keys_only, Volume& scratch)>;
/// Takes a volume band by band: `header` is the volume without its voxels (grid, density mode,
/// channels and their ranges, algorithm, depth, points), `load` gives its `bands` bands.
using VolumeBandSink = std::function<void(const Volume& header, std::size_t bands, const VolumeBandLoader& load)>;
/// @brief The bands of a grid: dims[0] / kVolumeBandRows, rounded up.
std::size_t volume_bands(const VoxelGrid& grid);
/// @brief A loader of the bands of a volume held whole (it points into `volume`).
VolumeBandLoader band_loader(const Volume& volume);

/// One output attribute per voxel: "color" (3 components, RGB in [0, 1]; HSI converted;
/// gray repeated), "gray", "alpha", or any other channel by its name (1 component, in [0, 1]).
struct VolumeAttribute {
  std::string name;
  int components = 1;
  std::vector<float> values;  ///< voxel-major, size() * components
};

/// How one exported attribute is made from a voxel's channel means: each channel scaled to
/// [0, 1] (a v + b, clamped; Eq. 101 for ranges), then taken as RGB, converted from HSI,
/// repeated (gray as colour) or taken alone.
struct AttributeRecipe {
  enum class Source { Rgb, Hsi, GrayAsRgb, Channel };
  std::string name;
  int components = 1;
  Source source = Source::Channel;
  int first = 0;                     ///< the first channel read
  std::vector<double> scale, offset;  ///< a and b of every channel
  /// @brief The attribute (`components` values) of a voxel with these channel means.
  void evaluate(const float* channels, float* out) const;
};

/// @brief The attributes a volume exports, in a fixed order (color first), as recipes.
std::vector<AttributeRecipe> attribute_recipes(const Volume& volume, ColorScale scale = ColorScale::Auto);

/// @brief The attributes a volume exports, evaluated for every voxel.
std::vector<VolumeAttribute> volume_attributes(const Volume& volume, ColorScale scale = ColorScale::Auto);

}  // namespace ifsforge
