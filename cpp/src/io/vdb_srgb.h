#pragma once
// The colour grid's linear halves (src/io only): openvdb::math::half(srgb_to_linear(c)) without
// a powf per value, bit for bit.
#include <cstdint>
#include <cstring>
#include <vector>

namespace ifsforge::detail {

/// @brief The bits of openvdb::math::half(srgb_to_linear<float>(c)) for every float c. Where
/// srgb_to_linear calls powf (0.04045 < c <= 1) the half is read from thresholds: the first c
/// whose half reaches each half value, found once with powf itself, so that a value's half is
/// the last threshold at or below it (one comparison with a table indexed by c's bits). That
/// holds because c -> half(srgb_to_linear(c)) never decreases, which the thresholds' search
/// checks where it looks and tests/cpp/test_vdb_stream.cpp checks for every float of the range;
/// should the search ever see it decrease, every value takes powf. Other values (c <= 0.04045,
/// a division; outside [0, 1]; NaN) are converted as they are.
class LinearHalves {
 public:
  /// @brief The table of this process (built on first use, about a millisecond).
  static const LinearHalves& get();
  std::uint16_t operator()(float c) const {
    std::uint32_t x;
    std::memcpy(&x, &c, sizeof x);
    x -= first_;
    if (x > span_ || !in_use_) return exact(c);  // also c <= 0.04045, negative, NaN
    // The bucket's half at its start (its group's, plus a step), one more past its threshold.
    const std::uint32_t i = x >> kShift, e = bucket_[i];
    return static_cast<std::uint16_t>(group_[i >> kGroupShift] + (e >> kShift) + ((x & kInBucket) > (e & kInBucket)));
  }
  /// @brief What the table stands for: the half of srgb_to_linear(c) by powf.
  static std::uint16_t exact(float c);
  /// @brief Whether the thresholds are in use (c -> half(srgb_to_linear(c)) was seen to never decrease).
  bool in_use() const { return in_use_; }

 private:
  LinearHalves();
  /// Floats per bucket: 2^kShift. Across a bucket srgb_to_linear grows by less than 2.4 times its
  /// relative width, 2.4 * 2^(kShift - 23), below the 2^-11 between two halves: one threshold at most.
  static constexpr int kShift = 10, kGroupShift = 6;  ///< buckets per group: 2^kGroupShift
  static constexpr std::uint32_t kInBucket = (1u << kShift) - 1;
  bool in_use_ = false;
  std::uint32_t first_ = 0;  ///< the bits of the first float read from the table
  std::uint32_t span_ = 0;   ///< the last's bits minus the first's
  /// Per bucket, 16 bits (77 KB in all, to stay in the cache): the half at its first float over
  /// its group's (< 64) << kShift | where its threshold is in it, less one (kInBucket: none).
  std::vector<std::uint16_t> bucket_;
  std::vector<std::uint16_t> group_;  ///< the half at each group's first float
};

}  // namespace ifsforge::detail
