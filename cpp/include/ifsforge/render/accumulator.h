#pragma once
/// @file Per-worker integer accumulation of hits, measure and channel values. Integer sums
/// are associative, so merging workers in any order gives the same bytes: this is what keeps
/// every renderer's output independent of the thread count.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "ifsforge/core/pages.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/raster.h"

namespace ifsforge {

class Accumulator {
 public:
  /// Channel values are quantised to 2^20 steps of [lo, hi] (clamped).
  static constexpr double kChannelSteps = 1048576.0;
  /// Measure is fixed point: 2^62 units are the whole mass of the attractor.
  static constexpr double kMassUnit = 4611686018427387904.0;

  Accumulator(int width, int height, bool measure, std::vector<double> channel_lo,
              std::vector<double> channel_hi);

  /// @brief Bytes one accumulator of this shape takes (for the memory budget).
  static double bytes(int width, int height, bool measure, int channels);

  int width() const { return width_; }
  int height() const { return height_; }
  int channels() const { return channels_; }
  std::uint64_t* hits() { return hits_.data(); }

  /// @brief One point (its channel values `values`, if any) lands in `pixel`, with `mass`
  /// (fraction of the total measure; ignored unless measure is on).
  void add(std::size_t pixel, const double* values, double mass = 0.0) {
    ++hits_[pixel];
    if (!mass_.empty()) mass_[pixel] += static_cast<std::uint64_t>(mass * kMassUnit + 0.5);
    for (int c = 0; c < channels_; ++c) sums_[pixel * channels_ + c] += quantised(c, values[c]);
  }
  /// @brief Channel `c`'s value in steps of its range: what add() sums (at most kChannelSteps).
  std::uint64_t quantised(int c, double value) const {
    double q = (value - lo_[c]) * scale_[c];
    q = q < 0.0 ? 0.0 : (q > kChannelSteps ? kChannelSteps : q);
    return static_cast<std::uint64_t>(q + 0.5);
  }
  /// @brief quantised()'s terms: channel `c`'s lower bound and steps per unit.
  double channel_lo(int c) const { return lo_[c]; }
  double channel_scale(int c) const { return scale_[c]; }
  /// @brief The channel sums, pixel-major (narrow per-worker counters add their wraps here).
  std::uint64_t* sums() { return sums_.data(); }
  /// @brief Asks for `pixel`'s counters ahead of its add(): a large image's counters miss the
  /// caches, and a loop that prefetches a few points ahead waits on several misses at once.
  void prefetch(std::size_t pixel) const {
    __builtin_prefetch(hits_.data() + pixel, 1);
    if (channels_) {
      __builtin_prefetch(sums_.data() + pixel * channels_, 1);
      __builtin_prefetch(sums_.data() + (pixel + 1) * channels_ - 1, 1);
    }
    if (!nearest_.empty()) __builtin_prefetch(nearest_.data() + pixel, 1);
  }
  /// @brief Keeps, per pixel, the largest depth towards the viewer (a z-buffer, 3D views).
  void enable_depth() { assign_large(nearest_, hits_.size(), -std::numeric_limits<float>::infinity()); }
  void add_depth(std::size_t pixel, double depth) {
    const float d = static_cast<float>(depth);
    if (d > nearest_[pixel]) nearest_[pixel] = d;
  }
  /// @brief Keeps the larger of each pixel's depth and `depth[pixel]` (one per pixel and the
  /// trash slot, as hits()).
  void merge_depth(const float* depth) {
    for (std::size_t i = 0; i < nearest_.size(); ++i) nearest_[i] = std::max(nearest_[i], depth[i]);
  }
  void merge(const Accumulator& other);
  /// @brief Sparse bytes for a cluster: the pixels holding hits (gaps between them, then
  /// their sums) as varints, depths as float bits.
  std::string encode() const;
  /// @brief merge() of the accumulator `bytes` came from (same shape); InputError otherwise.
  void merge_encoded(std::string_view bytes);
  /// @brief Density = mass (measure on) or hits; channel means from the sums; in pixel bands
  /// on `threads` threads (0: every core; each pixel on its own, so the same bytes).
  void finish(Raster& raster, int threads = 0) const;

 private:
  int width_, height_, channels_;
  ZeroedVector<std::uint64_t> hits_, mass_, sums_;
  LargeVector<float> nearest_;  // max is order-independent: merging stays deterministic
  std::vector<double> lo_, scale_;
};

/// @brief The channel ranges renderers quantise with: the attractor's bounds of every
/// non-spatial channel (empty for a purely spatial system).
void channel_ranges(const Ifs& ifs, std::vector<double>& lo, std::vector<double>& hi);

/// @brief Fills the raster's channel metadata from the system's layout.
void describe_channels(const Ifs& ifs, Raster& raster);

}  // namespace ifsforge
