#pragma once
/// @file Box-counting dimension of a binary image.
#include <cstdint>
#include <vector>

#include "ifsforge/render/raster.h"

namespace ifsforge {

struct BoxCounting {
  std::vector<int> box_sizes;            ///< in pixels, powers of two
  std::vector<std::uint64_t> box_counts; ///< boxes holding at least one covered pixel
  double dimension = 0.0;                ///< least-squares slope of log N against log(1/size)
};

/// @brief Box sizes a dimension is fitted over at the least (three doublings).
constexpr std::size_t kMinBoxSizes = 4;

/// @brief Counts covered boxes of side min_box, 2 min_box, ... up to max_box (default: 1/32
/// of the covered extent) and fits the dimension; InputError, saying what image size would
/// do, when that gives fewer than kMinBoxSizes sizes.
BoxCounting box_counting(const std::vector<std::uint8_t>& mask, int width, int height,
                         int min_box = 2, int max_box = 0);
/// @brief The same over the pixels a raster covers.
BoxCounting box_counting(const Raster& raster, int min_box = 2, int max_box = 0);

}  // namespace ifsforge
