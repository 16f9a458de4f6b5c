#pragma once
/// @file Image ↔ coded planes: 8-bit levels, the seed's Steps 1-2 for colour (YCbCr with the
/// chroma averaged to half resolution), padding to whole top-level blocks, cropping and resampling.
#include <array>
#include <vector>

#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"
#include "ifsforge/core/image.h"

namespace ifsforge {

/// @brief A `width`×`height` raster of `value` in huge pages, faulted in.
PifsRaster plane_raster(int width, int height, float value = 0.f);

/// @brief The width and height of each plane the encoder codes `image` as (unpadded): gray
/// [+ alpha], Y Cb Cr [+ alpha] for YCbCr444, the same with chroma at half size (rounded up) for
/// YCbCr420, else one plane per channel.
std::vector<std::array<int, 2>> plane_sizes(const Image& image, PifsColor color);

/// @brief The conversion's jobs: the image's rows, pairs of rows for YCbCr420.
int conversion_rows(const Image& image, PifsColor color);

/// @brief The planes' samples (values rounded to 8-bit levels) of jobs [begin, end) of
/// conversion_rows, written into `planes`: rasters at least plane_sizes large (a larger, padded
/// one keeps its other samples). Any split of the jobs gives the same planes (the encoder
/// converts on its rounds' threads).
void convert_rows(const Image& image, PifsColor color, std::vector<PifsRaster>& planes, int begin, int end);

/// @brief Rows [begin, end) of `padded`, whose top-left `width`×`height` samples are a plane,
/// filled past the plane by repeating its last column and row. Rows may be padded in any order,
/// side by side.
void pad_rows(PifsRaster& padded, int width, int height, int begin, int end);

/// @brief Threads for one pass over `pixels` pixels: one per whole 2^20, at least one and at most
/// `threads`. A thread shares a pass only when it gets 2^20 pixels of it: with less, waiting for
/// it to be scheduled on a loaded machine and the two cores' shared memory traffic cost more
/// than it saves (a 1024² pass took as long or longer on 2 threads as on 1).
int pass_threads(int threads, double pixels);

/// @brief The image from planes decoded at the same output size (chroma already at full size):
/// `width`×`height` taken from their top-left corners, converted back to RGB for YCbCr.
Image planes_to_image(const std::vector<PifsRaster>& planes, int channels, PifsColor color, int width,
                      int height, int threads = 1);

/// @brief Area-weighted resampling of `plane` to `width`×`height` (box filter; exact 2×2 mean for halving).
PifsRaster resample_area(const PifsRaster& plane, int width, int height);

/// @brief The mean squared RGB error (8-bit levels²) that averaging the chroma of `image` 2×2
/// alone costs (each pixel rebuilt from its own Y and its cell's chroma); 0 below 3 channels.
/// Pairs of rows are jobs on `threads` threads (parallel_jobs, with `progress`).
double chroma_halving_error(const Image& image, int threads = 1, const ProgressCallback& progress = nullptr);

/// @brief The mean squared error of `b` against `a` in 8-bit levels² (equal sizes); the same on
/// any number of threads.
double squared_error(const Image& a, const Image& b, int threads = 1);

}  // namespace ifsforge
