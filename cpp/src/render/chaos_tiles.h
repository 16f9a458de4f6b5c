#pragma once
/// @file Tiled accumulation of the chaos game's 2D hits: a batch of pixel slots is binned by
/// tile (a counting sort on the high bits of the slot) and then counted tile by tile, so each
/// tile's counters stay in the core's cache whatever the image's size. The counts are integer
/// sums, so the image is the same bytes as counting the points in the order they came.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ifsforge::lanes {

/// Images of more pixels than this (4096^2) are counted through tiles; up to it the direct
/// increments were as fast (a fern's points crowd into part of the image, which stays cached).
constexpr std::size_t kTiledAbovePixels = std::size_t(1) << 24;
/// Tiles of 2^18 counters (256 KB of bytes: half of a core's L2 on current x86-64).
constexpr int kTileShift = 18;
/// Slots per batch: enough that every tile of an 8192^2 image receives a few hundred points.
constexpr std::size_t kTileBatch = std::size_t(1) << 20;

/// One worker's binning scratch; add() counts a batch into 8-bit `low` counters whose wraps add
/// 256 to `carry` (atomically: workers share it).
class TiledCounter {
 public:
  TiledCounter(std::size_t slots, std::uint8_t* low, std::uint64_t* carry);
  void add(const std::uint32_t* slots, std::size_t n);
  /// The kernels' callback: `self` is a TiledCounter.
  static void flush(void* self, const std::uint32_t* slots, std::size_t n);

 private:
  std::vector<std::uint32_t> starts_, sorted_;
  std::uint8_t* low_;
  std::uint64_t* carry_;
};

}  // namespace ifsforge::lanes
