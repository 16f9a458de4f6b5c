#pragma once
/// @file The hits of a 2D lane render (chaos_game.cpp) turned into the raster without a 64-bit
/// counter per pixel: each worker counts into 8-bit counters, and the density is their sum plus
/// 256 for each wrap, made pixel by pixel. The kernels count a small image straight into the
/// counters and add the wraps to a 64-bit array (its pages mapped by the kernel only where a
/// counter wrapped; read elsewhere as the zero page); tiled counting (chaos_tiles.h) lists them
/// per tile instead. At 8192^2 the 512 MB of 64-bit hits an accumulator zeroes, the pass that
/// added the 8-bit counters into it and the finish that read it back were half a render's fixed
/// CPU time (a 1,024-point render: 0.31-0.52 s with them, 0.15-0.18 s without).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ifsforge/core/pages.h"
#include "ifsforge/render/raster.h"

namespace ifsforge::sinks {

struct LaneHits {
  /// `slots` counters (the pixels and the off-image slot), all zero, no page faulted in; `carry`
  /// only where the wraps go there (untiled counting).
  LaneHits(std::size_t slots, bool carry);
  /// 256 per wrap of a worker's 8-bit counter (atomic adds: the workers share it); empty when
  /// the wraps are listed.
  ZeroedVector<std::uint64_t> carry;
  /// Per worker, its 8-bit counters (empty: the worker ran no job).
  std::vector<ZeroedVector<std::uint8_t>> lows;
  /// Per worker and tile (lanes::kTileShift), TiledCounter::take_wraps().
  std::vector<std::vector<std::vector<std::uint16_t>>> wraps;
  /// The raster's size and density as Accumulator::finish makes it from the same counts (a
  /// count as a float, 0 where no point fell), in pixel bands on `threads` threads.
  void finish(Raster& raster, int width, int height, int threads) const;
};

}  // namespace ifsforge::sinks
