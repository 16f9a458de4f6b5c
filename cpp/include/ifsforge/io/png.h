#pragma once
/// @file PNG in and out (libpng reads, zlib writes: both stay behind this header).
#include <string>

#include "ifsforge/core/image.h"

namespace ifsforge {

/// @brief Writes `image` (1 gray, 2 gray+alpha, 3 RGB, 4 RGBA channels, values clamped to
/// [0, 1]) with 8 or 16 bits per sample, atomically; filtered and deflated on every core in
/// strips cut by size, so the bytes never depend on the thread count.
void write_png(const std::string& path, const Image& image, int bit_depth = 8);

/// @brief Reads any PNG (palette and low bit depths expanded) as floats in [0, 1], keeping
/// its channel count. InputError names the file when it is not a readable PNG.
Image read_png(const std::string& path);

}  // namespace ifsforge
