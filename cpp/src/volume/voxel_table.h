#pragma once
// A hash table of integer voxel sums, for points with no spatial locality (random iteration,
// volume rewriting). Open addressing with linear probing; private to the volume renderers.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "ifsforge/core/memory.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/volume/voxel_list.h"

namespace ifsforge {

/// Each slot holds key, hits, mass and the channel sums side by side, padded to a power of two
/// words and aligned, so that a point touches one cache line (up to five channels) rather than
/// one per array: random points miss the cache on every add.
class VoxelTable {
 public:
  /// The multiplier of the slots' Fibonacci hash: a key's slot is the top bits of key * kHash.
  static constexpr std::uint64_t kHash = 0x9E3779B97F4A7C15ull;
  /// `extremes`: whether voxels keep VoxelList::kExtremes points (merged by min / max).
  VoxelTable(int channels, bool extremes = false)
      : channels_(channels), extremes_(extremes ? VoxelList::kExtremes : 0), stride_(slot_words(channels, extremes)) {
    reset(1u << 12);
  }
  /// @brief Bytes a table spends per voxel it holds (slots at most 3/4 full, so at worst 3/8
  /// after growing): for estimates.
  static double bytes_per_voxel(int channels, bool extremes) { return 8.0 / 3.0 * 8.0 * slot_words(channels, extremes); }
  /// A copy holds the same voxels (its slots are aligned afresh, so base_ cannot be copied).
  VoxelTable(const VoxelTable& other) : VoxelTable(other.channels_, other.extremes_ > 0) {
    reset(other.capacity_);
    std::copy(other.base_, other.base_ + other.capacity_ * stride_, base_);
    used_ = other.used_;
  }
  VoxelTable(VoxelTable&&) = default;  // the buffer moves with its vector: base_ stays valid

  /// @brief Starts loading the slot `key` hashes to (the add that follows finds it in cache).
  void prefetch(std::uint64_t key) const {
    __builtin_prefetch(base_ + ((key * kHash) >> shift_) * stride_, 1);
  }

  /// @brief Adds `hits` hits with `mass` and quantised channel sums `values` to voxel `key`;
  /// with extremes, `points` holds the packed point in each of the kExtremes slots.
  void add(std::uint64_t key, std::uint64_t hits, std::uint64_t mass, const std::uint64_t* values,
           const std::uint64_t* points = nullptr) {
    bool fresh = false;
    std::uint64_t* s = claim(key, stride_, fresh);
    for (int e = 0; e < extremes_; ++e) {
      std::uint64_t& p = s[3 + channels_ + e];
      p = fresh ? points[e] : e % 2 ? std::max(p, points[e]) : std::min(p, points[e]);
    }
    s[1] += hits;
    s[2] += mass;
    for (int c = 0; c < channels_; ++c) s[3 + c] += values[c];
  }
  /// @brief add(key, 1, 1, values) for a table without extremes whose `Channels` channels are
  /// known when compiled: random iteration's one hit per point, inlined in its loops (the
  /// same probes, so the same slots and sums).
  template <int Channels>
  void add_hit(std::uint64_t key, const std::uint64_t* values) {
    bool fresh = false;
    std::uint64_t* s = claim(key, slot_words(Channels, false), fresh);
    s[1] += 1;
    s[2] += 1;
    for (int c = 0; c < Channels; ++c) s[3 + c] += values[c];
  }
  /// @brief Bytes of the slots.
  std::size_t bytes() const { return capacity_ * stride_ * sizeof(std::uint64_t); }
  /// @brief Reads the slots of region `region` of 2^`bits` (the slots whose index starts with
  /// those bits) in order, one word per cache line, bringing them into cache (voxel_bins.h).
  void warm(std::size_t region, int bits) const {
    const int index_bits = 64 - shift_;
    if (bits > index_bits) return;
    const std::size_t first = region << (index_bits - bits), count = std::size_t(1) << (index_bits - bits);
    const std::size_t step = std::max<std::size_t>(1, 8 / stride_);  // slots per cache line
    std::uint64_t any = 0;
    for (std::size_t slot = first; slot < first + count; slot += step) any |= base_[slot * stride_];
    asm volatile("" : : "r"(any));
  }
  /// @brief Hits of voxel `key`; 0 when no point fell in it.
  std::uint64_t hits_of(std::uint64_t key) const {
    std::size_t slot = (key * kHash) >> shift_;
    for (const std::uint64_t* s = base_ + slot * stride_; s[0] != kEmpty; s = base_ + slot * stride_) {
      if (s[0] == key) return s[1];
      slot = (slot + 1) & mask_;
    }
    return 0;
  }
  /// @brief Calls `visit(key, hits)` for every occupied voxel, in slot order.
  template <class Visit>
  void for_each(Visit visit) const {
    for (const std::uint64_t *s = base_, *end = base_ + capacity_ * stride_; s != end; s += stride_)
      if (s[0] != kEmpty) visit(s[0], s[1]);
  }
  /// @brief The occupied voxels, sorted. The table is emptied (keeping its capacity, so that
  /// a worker reusing it for the next job does not allocate again).
  VoxelList take() {
    VoxelList list(channels_);
    list.reserve(used_);  // every array, not only the keys: no regrowth while the slots are read
    for (std::size_t slot = 0; slot < capacity_; ++slot) {
      const std::uint64_t* s = at(slot);
      if (s[0] == kEmpty) continue;
      list.push(s[0], s[1], s[2], s + 3);
      list.points.insert(list.points.end(), s + 3 + channels_, s + 3 + channels_ + extremes_);
    }
    sort_and_reduce(list);
    reset(capacity_);
    return list;
  }

 private:
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);

  /// The slot of voxel `key` (`stride` words a slot: stride_, or the same known when compiled),
  /// its key written and `fresh` set if it is new. At most 3/4 full: linear probing still finds
  /// a voxel in ~2.5 slots, and the table stays half the size it would be at 1/2 (random adds
  /// miss the cache in proportion); a new voxel past that grows the table first.
  std::uint64_t* claim(std::uint64_t key, std::size_t stride, bool& fresh) {
    std::size_t slot = (key * kHash) >> shift_;
    std::uint64_t* s = base_ + slot * stride;
    while (s[0] != key) {
      if (s[0] == kEmpty) {
        if (4 * (used_ + 1) > 3 * capacity_) {
          grow();
          slot = (key * kHash) >> shift_;
          s = base_ + slot * stride;
          continue;
        }
        s[0] = key;
        ++used_;
        fresh = true;
        break;
      }
      slot = (slot + 1) & mask_;
      s = base_ + slot * stride;
    }
    return s;
  }

  static constexpr std::size_t slot_words(int channels, bool extremes) {
    std::size_t words = 4;
    while (words < std::size_t(3 + channels + (extremes ? VoxelList::kExtremes : 0))) words *= 2;
    return words;
  }

  std::uint64_t* at(std::size_t slot) { return base_ + slot * stride_; }

  void reset(std::size_t capacity) {
    // One cache line of slack to align the slots on 64 bytes. Huge pages where the kernel
    // grants them: random adds touch every page, and a 16 MB table spans 4096 small ones (more
    // than the TLB holds) but only 8 huge ones.
    assign_large(data_, capacity * stride_ + 8, std::uint64_t(0));
    const auto address = reinterpret_cast<std::uintptr_t>(data_.data());
    base_ = data_.data() + ((64 - address % 64) % 64) / sizeof(std::uint64_t);
    for (std::size_t slot = 0; slot < capacity; ++slot) base_[slot * stride_] = kEmpty;
    capacity_ = capacity;
    mask_ = capacity - 1;
    shift_ = 64;
    for (std::size_t c = capacity; c > 1; c >>= 1) --shift_;
    used_ = 0;
  }
  void grow() {
    check_memory(2.0 * capacity_ * stride_ * 8.0 * 2.0, "a voxel hash table");
    std::vector<std::uint64_t> old;
    old.swap(data_);
    const std::uint64_t* old_base = base_;
    const std::size_t old_capacity = capacity_;
    reset(old_capacity * 2);
    for (std::size_t slot = 0; slot < old_capacity; ++slot) {
      const std::uint64_t* from = old_base + slot * stride_;
      if (from[0] == kEmpty) continue;
      std::size_t to = (from[0] * kHash) >> shift_;
      while (at(to)[0] != kEmpty) to = (to + 1) & mask_;
      std::copy(from, from + stride_, at(to));
      ++used_;
    }
  }

  int channels_, extremes_;
  std::size_t stride_;
  std::vector<std::uint64_t> data_;
  std::uint64_t* base_ = nullptr;
  std::size_t capacity_ = 0, mask_ = 0, used_ = 0;
  int shift_ = 64;
};

}  // namespace ifsforge
