#pragma once
/// @file Tiled accumulation of the chaos game's 2D hits. Each slot goes to its tile's bin (the
/// high bits of the slot pick the tile, the low 16 bits are kept); a full bin is counted into its
/// tile at once. A bin holds many more points than its tile has cache lines, so a tile's counters
/// are fetched once for several points each whatever the image's size, instead of once a point.
/// A point reaches its bin through its tile's stage, one cache line written whole when full: at
/// 8192^2 there are a thousand bins, and writing each point straight into its bin fetched the
/// bin's line from memory first, one miss every few points. Past 256 tiles the stages outgrow
/// L1, and each point's stage line is prefetched a few points ahead.
/// The counts are integer sums, so the image is the same bytes as counting the points in the
/// order they came. A counter's wraps are kept in a list per tile, not added to a 64-bit array
/// per pixel: such an array is most of a large render's fixed cost (chaos_hits.h), and a wrap
/// is rare (at 8192^2, 2e8 fern points wrap 82,000 of 7.8 M covered pixels).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "ifsforge/core/pages.h"

namespace ifsforge::lanes {

/// Images of at least this many pixels (4096^2) are counted through tiles; below it the direct
/// increments were as fast (the image's 8-bit counters stay in the shared cache).
constexpr std::size_t kTiledFromPixels = std::size_t(1) << 24;
/// kTiledFromPixels, or IFSFORGE_CHAOS_TILES_FROM pixels where set: tests lower it to compare
/// tiled and direct counts on small, dense images (every bin filled many times, every counter
/// wrapped).
std::size_t tiled_from_pixels();
/// Tiles of 2^16 counters: 64 KB of 8-bit counters, an eighth of a core's L2 on current x86-64.
constexpr int kTileShift = 16;
/// Points a bin holds before it is counted: 32 per cache line of its tile (64 KB of offsets).
constexpr std::size_t kBinPoints = std::size_t(1) << 15;
/// Points a tile stages before they go to its bin: one cache line of 16-bit offsets.
constexpr std::size_t kStagePoints = 32;
/// Slots per batch from the kernel: small enough to stay in L1 until binned.
constexpr std::size_t kTileBatch = std::size_t(1) << 12;

/// One worker's bins; add() bins a batch, drain() counts what the bins still hold. Counting goes
/// into 8-bit `low` counters; each wrap (256 more hits) is noted in its tile's list of wraps.
class TiledCounter {
 public:
  TiledCounter(std::size_t slots, std::uint8_t* low);
  ~TiledCounter();
  TiledCounter(const TiledCounter&) = delete;
  TiledCounter& operator=(const TiledCounter&) = delete;
  void add(const std::uint32_t* slots, std::size_t n);
  void drain();
  /// The kernels' callback: `self` is a TiledCounter.
  static void flush(void* self, const std::uint32_t* slots, std::size_t n);
  /// Bytes of bins and stages for an image of `slots` counters.
  static std::size_t bytes(std::size_t slots);
  /// Per tile, the offsets within it (slot & 0xFFFF) of the counters that wrapped, once a wrap.
  std::vector<std::vector<std::uint16_t>> take_wraps() { return std::move(wraps_); }

 private:
  template <bool kPrefetch>
  void stage(const std::uint32_t* slots, std::size_t n);
  void unstage(std::size_t tile);
  void count(std::size_t tile, const std::uint16_t* offsets, std::size_t n);

  std::size_t tiles_;
  std::size_t bytes_;
  void* storage_;         ///< allocate_pages(bytes_)
  std::uint16_t* bins_;   ///< kBinPoints offsets per tile, then kStagePoints per tile (the stages)
  std::uint16_t* stage_;  ///< the stages: 64-byte aligned, one cache line per tile
  std::vector<std::uint16_t*> fill_;    ///< the next free place of each tile's bin
  std::vector<std::uint16_t*> staged_;  ///< the next free place of each tile's stage
  std::uint8_t* low_;
  std::vector<std::vector<std::uint16_t>> wraps_;  ///< per tile
};

}  // namespace ifsforge::lanes
