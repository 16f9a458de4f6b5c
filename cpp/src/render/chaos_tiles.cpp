#include "chaos_tiles.h"

namespace ifsforge::lanes {

namespace {
std::size_t tiles_of(std::size_t slots) { return (slots + (std::size_t(1) << kTileShift) - 1) >> kTileShift; }
}  // namespace

TiledCounter::TiledCounter(std::size_t slots, std::uint8_t* low, std::uint64_t* carry)
    : fill_(tiles_of(slots)), bytes_(bytes(slots)),
      // Not zeroed: a bin's pages are first touched by its first point.
      bins_(static_cast<std::uint16_t*>(allocate_pages(bytes_))), low_(low), carry_(carry) {
  for (std::size_t t = 0; t < fill_.size(); ++t) fill_[t] = bins_ + t * kBinPoints;
}

TiledCounter::~TiledCounter() { release_pages(bins_, bytes_); }

std::size_t TiledCounter::bytes(std::size_t slots) { return tiles_of(slots) * kBinPoints * sizeof(std::uint16_t); }

void TiledCounter::add(const std::uint32_t* slots, std::size_t n) {
  std::uint16_t* const bins = bins_;
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t s = slots[i];
    const std::size_t tile = s >> kTileShift;
    std::uint16_t* place = fill_[tile];
    *place++ = static_cast<std::uint16_t>(s);
    fill_[tile] = place;
    if (place == bins + (tile + 1) * kBinPoints) count(tile);
  }
}

void TiledCounter::count(std::size_t tile) {
  std::uint16_t* const bin = bins_ + tile * kBinPoints;
  const std::size_t n = static_cast<std::size_t>(fill_[tile] - bin);
  std::uint8_t* const low = low_ + (tile << kTileShift);
  std::uint64_t* const carry = carry_ + (tile << kTileShift);
  for (std::size_t i = 0; i < n; ++i)
    if (++low[bin[i]] == 0) __atomic_fetch_add(carry + bin[i], 256, __ATOMIC_RELAXED);
  fill_[tile] = bin;
}

void TiledCounter::drain() {
  for (std::size_t t = 0; t < fill_.size(); ++t) count(t);
}

void TiledCounter::flush(void* self, const std::uint32_t* slots, std::size_t n) {
  static_cast<TiledCounter*>(self)->add(slots, n);
}

}  // namespace ifsforge::lanes
