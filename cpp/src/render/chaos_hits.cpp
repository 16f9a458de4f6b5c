#include "chaos_hits.h"

#include <algorithm>

#include "ifsforge/core/parallel.h"
#include "chaos_tiles.h"

namespace ifsforge::sinks {

LaneHits::LaneHits(std::size_t slots, bool with_carry) {
  // Sized from empty: the zero-page allocator writes nothing (zeroed_large would fault every
  // page in ahead, the cost this type is here to avoid).
  if (with_carry) carry.resize(slots);
}

void LaneHits::finish(Raster& raster, int width, int height, int threads) const {
  const std::size_t pixels = std::size_t(width) * height;
  raster.width = width;
  raster.height = height;
  assign_large(raster.density, pixels, 0.0f);
  assign_large(raster.channels, 0, 0.0f);
  std::vector<const std::uint8_t*> counted;
  for (const auto& low : lows)
    if (!low.empty()) counted.push_back(low.data());
  const std::uint64_t* const wide = carry.empty() ? nullptr : carry.data();
  // A count of 0 is the float 0 Accumulator::finish leaves, any other at least 1, above the
  // smallest float it clamps a density to: one formula for every pixel, without a branch.
  auto hits = [&](std::size_t i) {
    std::uint64_t sum = wide ? wide[i] : 0;
    for (const std::uint8_t* low : counted) sum += low[i];
    return sum;
  };
  // Bands of one tile each: a band's listed wraps are its tile's.
  constexpr std::size_t kBand = std::size_t(1) << lanes::kTileShift;
  parallel_jobs((pixels + kBand - 1) / kBand, threads, [&](std::size_t band, int) {
    const std::size_t from = band * kBand, to = std::min(pixels, from + kBand);
    float* const density = raster.density.data();
    if (!wide && counted.size() == 1) {  // one worker, tiled: the common large render
      const std::uint8_t* const low = counted[0];
      for (std::size_t i = from; i < to; ++i) density[i] = static_cast<float>(static_cast<double>(low[i]));
    } else {
      for (std::size_t i = from; i < to; ++i) density[i] = static_cast<float>(static_cast<double>(hits(i)));
    }
    // The band's wraps, each 256 more hits: sorted, every wrapped pixel's count made once.
    std::vector<std::uint16_t> wrapped;
    for (const auto& worker : wraps)
      if (band < worker.size()) wrapped.insert(wrapped.end(), worker[band].begin(), worker[band].end());
    std::sort(wrapped.begin(), wrapped.end());
    for (std::size_t k = 0; k < wrapped.size();) {
      std::size_t run = k;
      while (run < wrapped.size() && wrapped[run] == wrapped[k]) ++run;
      const std::size_t i = from + wrapped[k];
      if (i < to) density[i] = static_cast<float>(static_cast<double>(hits(i) + 256 * (run - k)));
      k = run;
    }
  });
}

}  // namespace ifsforge::sinks
