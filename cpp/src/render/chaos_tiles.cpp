#include "chaos_tiles.h"

#include <cstdlib>
#include <string>

#include "ifsforge/core/stream_lines.h"

namespace ifsforge::lanes {

namespace {
constexpr std::size_t kStageBytes = kStagePoints * sizeof(std::uint16_t);
static_assert(kStageBytes == 64, "a stage is one cache line");
/// Stages of up to 16 KB (256 tiles: 4096^2 pixels) stay in a 32 KB L1 data cache beside the
/// batch (kTileBatch slots, 16 KB); beyond it each point's stage line is prefetched.
constexpr std::size_t kStagesInL1 = std::size_t(16) << 10;
/// How many points ahead a stage's line is prefetched: a few L2 latencies of the staging loop.
constexpr std::size_t kStageAhead = 16;

std::size_t tiles_of(std::size_t slots) { return (slots + (std::size_t(1) << kTileShift) - 1) >> kTileShift; }

}  // namespace

std::size_t tiled_from_pixels() {
  const char* from = std::getenv("IFSFORGE_CHAOS_TILES_FROM");
  return from && *from ? std::stoull(from) : kTiledFromPixels;
}

TiledCounter::TiledCounter(std::size_t slots, std::uint8_t* low)
    : tiles_(tiles_of(slots)), bytes_(bytes(slots)),
      // Not zeroed: a bin's pages are first touched by its first point. Lines from a line's start
      // (small storage comes from operator new).
      storage_(allocate_pages(bytes_)),
      bins_(reinterpret_cast<std::uint16_t*>((reinterpret_cast<std::uintptr_t>(storage_) + kStageBytes - 1) &
                                             ~std::uintptr_t(kStageBytes - 1))),
      stage_(bins_ + tiles_ * kBinPoints),
      fill_(tiles_), staged_(tiles_), low_(low), wraps_(tiles_) {
  for (std::size_t t = 0; t < tiles_; ++t) {
    fill_[t] = bins_ + t * kBinPoints;
    staged_[t] = stage_ + t * kStagePoints;
  }
}

TiledCounter::~TiledCounter() { release_pages(storage_, bytes_); }

std::size_t TiledCounter::bytes(std::size_t slots) {
  return tiles_of(slots) * (kBinPoints + kStagePoints) * sizeof(std::uint16_t) + kStageBytes;
}

void TiledCounter::add(const std::uint32_t* slots, std::size_t n) {
  if (tiles_ * kStageBytes > kStagesInL1)
    stage<true>(slots, n);
  else
    stage<false>(slots, n);
}

template <bool kPrefetch>
void TiledCounter::stage(const std::uint32_t* slots, std::size_t n) {
  std::uint16_t** const staged = staged_.data();
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t s = slots[i];
    const std::size_t tile = s >> kTileShift;
    // Stages beyond L1: the stage line of the point kStageAhead on is fetched now, so neither
    // its store nor its unstaging waits for it (at 8192^2 unstaging took half the time).
    if (kPrefetch && i + kStageAhead < n) __builtin_prefetch(staged[slots[i + kStageAhead] >> kTileShift], 1);
    std::uint16_t* place = staged[tile];
    *place++ = static_cast<std::uint16_t>(s);
    staged[tile] = place;
    // Stages are cache lines: the next place is a line's start when this one is full.
    if ((reinterpret_cast<std::uintptr_t>(place) & (kStageBytes - 1)) == 0) unstage(tile);
  }
}

void TiledCounter::unstage(std::size_t tile) {
  std::uint16_t* const stage = stage_ + tile * kStagePoints;
  std::uint16_t* const bin = bins_ + tile * kBinPoints;
  stream_lines(fill_[tile], stage, 1);  // whole: the bin's line is not read first
  staged_[tile] = stage;
  if ((fill_[tile] += kStagePoints) < bin + kBinPoints) return;
  count(tile, bin, kBinPoints);
  fill_[tile] = bin;
}

void TiledCounter::count(std::size_t tile, const std::uint16_t* offsets, std::size_t n) {
  std::uint8_t* const low = low_ + (tile << kTileShift);
  for (std::size_t i = 0; i < n; ++i)
    if (++low[offsets[i]] == 0) wraps_[tile].push_back(offsets[i]);
}

void TiledCounter::drain() {
  for (std::size_t t = 0; t < tiles_; ++t) {
    std::uint16_t* const bin = bins_ + t * kBinPoints;
    std::uint16_t* const stage = stage_ + t * kStagePoints;
    count(t, bin, static_cast<std::size_t>(fill_[t] - bin));
    count(t, stage, static_cast<std::size_t>(staged_[t] - stage));
    fill_[t] = bin;
    staged_[t] = stage;
  }
}

void TiledCounter::flush(void* self, const std::uint32_t* slots, std::size_t n) {
  static_cast<TiledCounter*>(self)->add(slots, n);
}

}  // namespace ifsforge::lanes
