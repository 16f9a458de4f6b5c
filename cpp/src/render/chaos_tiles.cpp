#include "chaos_tiles.h"

#include <algorithm>

namespace ifsforge::lanes {

TiledCounter::TiledCounter(std::size_t slots, std::uint8_t* low, std::uint64_t* carry)
    : starts_(((slots + (std::size_t(1) << kTileShift) - 1) >> kTileShift) + 1), sorted_(kTileBatch),
      low_(low), carry_(carry) {}

void TiledCounter::add(const std::uint32_t* slots, std::size_t n) {
  // Counting sort by tile: sizes, starts, then each slot into its tile's run.
  std::fill(starts_.begin(), starts_.end(), 0u);
  for (std::size_t i = 0; i < n; ++i) ++starts_[(slots[i] >> kTileShift) + 1];
  for (std::size_t t = 1; t < starts_.size(); ++t) starts_[t] += starts_[t - 1];
  for (std::size_t i = 0; i < n; ++i) sorted_[starts_[slots[i] >> kTileShift]++] = slots[i];
  // Counting a tile's run: its counters were last touched a batch ago, so the lines a few
  // points ahead are fetched while these are counted.
  constexpr std::size_t kAhead = 16;
  for (std::size_t i = 0; i < n; ++i) {
    if (i + kAhead < n) __builtin_prefetch(low_ + sorted_[i + kAhead], 1);
    const std::uint32_t s = sorted_[i];
    if (++low_[s] == 0) __atomic_fetch_add(carry_ + s, 256, __ATOMIC_RELAXED);
  }
}

void TiledCounter::flush(void* self, const std::uint32_t* slots, std::size_t n) {
  static_cast<TiledCounter*>(self)->add(slots, n);
}

}  // namespace ifsforge::lanes
