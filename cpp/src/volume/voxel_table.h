#pragma once
// A hash table of integer voxel sums, for points with no spatial locality (random iteration,
// volume rewriting). Open addressing with linear probing; private to the volume renderers.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "ifsforge/core/memory.h"
#include "ifsforge/volume/voxel_list.h"

namespace ifsforge {

class VoxelTable {
 public:
  /// `extremes`: whether voxels keep VoxelList::kExtremes points (merged by min / max).
  VoxelTable(int channels, bool extremes = false) : channels_(channels), extremes_(extremes ? VoxelList::kExtremes : 0) {
    reset(1u << 12);
  }

  /// @brief Adds `hits` hits with `mass` and quantised channel sums `values` to voxel `key`;
  /// with extremes, `points` holds the packed point in each of the kExtremes slots.
  void add(std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* values,
           const std::uint64_t* points = nullptr) {
    std::size_t slot = (key * 0x9E3779B97F4A7C15ull) >> shift_;
    while (keys_[slot] != kEmpty && keys_[slot] != key) slot = (slot + 1) & mask_;
    if (keys_[slot] == kEmpty) {
      if (2 * (used_ + 1) > keys_.size()) {
        grow();
        add(key, hits, mass, values, points);
        return;
      }
      keys_[slot] = key;
      ++used_;
      for (int e = 0; e < extremes_; ++e) points_[slot * extremes_ + e] = points[e];
    } else {
      for (int e = 0; e < extremes_; ++e) {
        std::uint64_t& p = points_[slot * extremes_ + e];
        p = e % 2 ? std::max(p, points[e]) : std::min(p, points[e]);
      }
    }
    hits_[slot] += hits;
    mass_[slot] += mass;
    for (int c = 0; c < channels_; ++c) sums_[slot * channels_ + c] += values[c];
  }
  /// @brief The occupied voxels, sorted. The table is emptied (keeping its capacity, so that
  /// a worker reusing it for the next job does not allocate again).
  VoxelList take() {
    VoxelList list(channels_);
    list.keys.reserve(used_);
    for (std::size_t s = 0; s < keys_.size(); ++s)
      if (keys_[s] != kEmpty) {
        list.push(keys_[s], hits_[s], mass_[s], sums_.data() + s * channels_);  // sums_ is empty without channels
        list.points.insert(list.points.end(), points_.begin() + s * extremes_, points_.begin() + (s + 1) * extremes_);
      }
    sort_and_reduce(list);
    reset(keys_.size());
    return list;
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);

  void reset(std::size_t capacity) {
    keys_.assign(capacity, kEmpty);
    hits_.assign(capacity, 0);
    mass_.assign(capacity, 0);
    sums_.assign(capacity * channels_, 0);
    points_.assign(capacity * extremes_, 0);
    mask_ = capacity - 1;
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c >>= 1) --shift_;
    used_ = 0;
  }
  void grow() {
    check_memory(2.0 * keys_.size() * (24.0 + 8.0 * (channels_ + extremes_)) * 2.0, "a voxel hash table");
    std::vector<std::uint64_t> keys, hits, mass, sums, points;
    keys.swap(keys_);
    hits.swap(hits_);
    mass.swap(mass_);
    sums.swap(sums_);
    points.swap(points_);
    reset(keys.size() * 2);
    for (std::size_t s = 0; s < keys.size(); ++s) {
      if (keys[s] == kEmpty) continue;
      std::size_t slot = (keys[s] * 0x9E3779B97F4A7C15ull) >> shift_;
      while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
      keys_[slot] = keys[s];
      hits_[slot] = hits[s];
      mass_[slot] = mass[s];
      for (int c = 0; c < channels_; ++c) sums_[slot * channels_ + c] = sums[s * channels_ + c];
      for (int e = 0; e < extremes_; ++e) points_[slot * extremes_ + e] = points[s * extremes_ + e];
      ++used_;
    }
  }

  int channels_, extremes_;
  std::vector<std::uint64_t> keys_, hits_, mass_, sums_, points_;
  std::size_t mask_ = 0, used_ = 0;
  int shift_ = 64;
};

}  // namespace ifsforge
