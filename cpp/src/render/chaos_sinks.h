#pragma once
/// @file Where the chaos game's points go (chaos_game.cpp): a worker's accumulator, the narrow
/// counters of a purely spatial system, or the packed records of a 2D system with channels.
/// Each takes a point of the one-job loop (add: the point's channel values, quantised here) and a
/// batch of the chain lanes (add_batch: the levels and float depths chaos_chains.h's kernels made).
#include <cstddef>
#include <cstdint>

#include "ifsforge/render/accumulator.h"
#include "chaos_chains.h"
#include "chaos_lanes.h"

namespace ifsforge::sinks {

using lanes::HitDepth;

/// Where the general path's points go: a worker's accumulator (channels carried)...
struct AccumulatorSink {
  Accumulator& acc;
  void prefetch(std::size_t pixel) const { acc.prefetch(pixel); }
  const void* counters() const { return acc.hits(); }  // the chain lanes' prefetch (chaos_chains.h)
  std::size_t counter_bytes() const { return sizeof(std::uint64_t); }
  std::uint32_t* packed_records() const { return nullptr; }  // the batches come to add_batch
  std::uint64_t* packed_carry() const { return nullptr; }
  void add(std::size_t pixel, const double* channels, bool depth, double toward) const {
    acc.add(pixel, channels);
    if (depth) acc.add_depth(pixel, toward);
  }
  /// A batch of the chain lanes (chains::Job::flush): levels already quantised, depths floats.
  void add_batch(const std::uint32_t* slots, const std::uint32_t* levels, const float* depths, std::size_t n) const {
    std::uint64_t* hits = acc.hits();
    std::uint64_t* sums = acc.sums();
    const int channels = acc.channels();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t pixel = slots[i];
      ++hits[pixel];
      for (int c = 0; c < channels; ++c) sums[pixel * channels + c] += levels[c * chains::kStride + i];
      if (depths) acc.add_depth(pixel, depths[i]);
    }
  }
};

/// ... or, for a purely spatial system, the narrow counters the lanes count into: 8-bit hits
/// whose wraps add 256 to the shared totals (2D), or 32-bit hits beside the largest depth (3D).
/// A large image's counters then stay in the caches (integer sums and a maximum: the same bytes).
struct NarrowSink {
  std::uint8_t* low;
  std::uint64_t* carry;
  HitDepth* cells;
  void prefetch(std::size_t pixel) const { __builtin_prefetch(cells ? (void*)(cells + pixel) : (void*)(low + pixel), 1); }
  const void* counters() const { return cells ? (const void*)cells : (const void*)low; }
  std::size_t counter_bytes() const { return cells ? sizeof(HitDepth) : 1; }
  std::uint32_t* packed_records() const { return nullptr; }  // the batches come to add_batch
  std::uint64_t* packed_carry() const { return nullptr; }
  void add(std::size_t pixel, const double*, bool depth, double toward) const {
    if (!cells) {
      if (++low[pixel] == 0) __atomic_fetch_add(carry + pixel, 256, __ATOMIC_RELAXED);
      return;
    }
    HitDepth& cell = cells[pixel];
    ++cell.hits;
    const float d = static_cast<float>(toward);  // as Accumulator::add_depth
    if (depth && d > cell.depth) cell.depth = d;
  }
  void add_batch(const std::uint32_t* slots, const std::uint32_t*, const float* depths, std::size_t n) const {
    if (!cells) {
      for (std::size_t i = 0; i < n; ++i)
        if (++low[slots[i]] == 0) __atomic_fetch_add(carry + slots[i], 256, __ATOMIC_RELAXED);
      return;
    }
    for (std::size_t i = 0; i < n; ++i) {
      HitDepth& cell = cells[slots[i]];
      ++cell.hits;
      if (depths[i] > cell.depth) cell.depth = depths[i];
    }
  }
};

/// ... or, for a 2D system with channels, per pixel 32-bit hits and each channel's quantised
/// sum in 32 bits (its wraps add 2^32 to the shared totals): one record per pixel, in cache.
struct ChannelSink {
  std::uint32_t* cells;
  std::uint64_t* carry;  // the wide accumulator's channel sums
  const Accumulator* acc;
  int channels;
  void prefetch(std::size_t pixel) const {
    __builtin_prefetch(cells + pixel * (channels + 1), 1);
    __builtin_prefetch(cells + pixel * (channels + 1) + channels, 1);
  }
  const void* counters() const { return cells; }
  std::size_t counter_bytes() const { return sizeof(std::uint32_t) * (channels + 1); }
  /// Three channels: a record is four 32-bit words, which the chain lanes add themselves
  /// (chains::Job::records), in their own instruction set; other counts come to add_batch.
  std::uint32_t* packed_records() const { return channels == 3 ? cells : nullptr; }
  std::uint64_t* packed_carry() const { return channels == 3 ? carry : nullptr; }
  void add(std::size_t pixel, const double* values, bool, double) const {
    std::uint32_t levels[chains::kMaxDim];
    for (int c = 0; c < channels; ++c) levels[c] = static_cast<std::uint32_t>(acc->quantised(c, values[c]));
    add_levels(channels, pixel, levels, 1);
  }
  /// The channel count a template argument for the common counts (the loop over them unrolls).
  void add_batch(const std::uint32_t* slots, const std::uint32_t* levels, const float*, std::size_t n) const {
    switch (channels) {
      case 1: return add_batch<1>(slots, levels, n);
      case 2: return add_batch<2>(slots, levels, n);
      case 3: return add_batch<3>(slots, levels, n);
      case 4: return add_batch<4>(slots, levels, n);
      default:
        for (std::size_t i = 0; i < n; ++i) add_levels(channels, slots[i], levels + i, chains::kStride);
    }
  }
  template <int kChannels>
  void add_batch(const std::uint32_t* slots, const std::uint32_t* levels, std::size_t n) const {
    for (std::size_t i = 0; i < n; ++i) add_levels(kChannels, slots[i], levels + i, chains::kStride);
  }
  /// Channel c's level at levels[c * stride].
  void add_levels(int count, std::size_t pixel, const std::uint32_t* levels, std::size_t stride) const {
    std::uint32_t* cell = cells + pixel * (count + 1);
    ++cell[0];
    for (int c = 0; c < count; ++c) {
      const std::uint32_t q = levels[c * stride], sum = cell[1 + c] + q;
      if (sum < q) __atomic_fetch_add(carry + pixel * count + c, std::uint64_t(1) << 32, __ATOMIC_RELAXED);
      cell[1 + c] = sum;
    }
  }
};

}  // namespace ifsforge::sinks
