#pragma once
/// @file The post-filter of a magnified decode (seed 3.3.2.2's resolution independence put to
/// use): the fractal decode at 2^k × a plane's size keeps only a share of its detail, on top of the
/// bicubic upscale of the native decode, and is then back-projected so that its 2^k × 2^k means
/// give the native decode again.
#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

/// @brief Share of the fractal decode in the magnified image (the rest: the bicubic upscale of the
/// native decode). Tuned on the training photos of cpp/bench/pifs_zoom.py at 2× and 4×; more
/// fractal detail sharpens but costs PSNR on smooth photos.
constexpr float kZoomFractalShare = 0.2f;

/// @brief Back-projection passes (each: the error of the 2^k × 2^k means against the native decode,
/// upscaled bicubic and added). One pass gains most; more pull in the native decode's own coding
/// error and lose at 4×.
constexpr int kZoomBackProjections = 1;

/// @brief `raster` magnified 2^log_factor times by Keys' cubic convolution (a = −1/2, the
/// "bicubic" of image tools), pixel centres aligned, edges repeated. The same on any `threads`.
PifsRaster upscale_bicubic(const PifsRaster& raster, int log_factor, int threads = 1);

/// @brief The magnified plane: `fractal` (the decode at 2^log_factor × `native`'s size) blended
/// with the bicubic upscale of `native` by kZoomFractalShare, then back-projected onto `native`
/// kZoomBackProjections times. The same on any `threads`.
PifsRaster zoom_filter(const PifsRaster& fractal, const PifsRaster& native, int log_factor, int threads = 1);

}  // namespace ifsforge
