#pragma once
/// @file The post-filter of a magnified decode (seed 3.3.2.2's resolution independence put to
/// use): the fractal decode at 2^k × a plane's size keeps only a share of its detail, on top of the
/// bicubic upscale of the native decode, and is then back-projected toward images whose 2^k × 2^k
/// means give the native decode again.
#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

/// @brief The filter at one magnification: `fractal_share` of the fractal decode (the rest: the
/// bicubic upscale of the native decode), then one back-projection pass weighted by
/// `back_projection` (the error of the f×f means against the native decode, upscaled bicubic and
/// added; 1 is the classic full step, 0 none).
struct ZoomSettings {
  float fractal_share;
  float back_projection;
};

/// @brief The settings at 2× and at 4× and above, chosen on the training photos of
/// cpp/bench/pifs_zoom.py (its --sweep) for the most photos improved over bicubic: more fractal
/// detail sharpens but costs PSNR on smooth photos; a full back-projection gains most on average
/// but pulls in the native decode's coding error at high ratios and at 4×.
constexpr ZoomSettings kZoomAt2{0.2f, 0.25f};
constexpr ZoomSettings kZoomAt4{0.1f, 0.f};

/// @brief `raster` magnified 2^log_factor times by Keys' cubic convolution (a = −1/2, the
/// "bicubic" of image tools), pixel centres aligned, edges repeated. The same on any `threads`.
PifsRaster upscale_bicubic(const PifsRaster& raster, int log_factor, int threads = 1);

/// @brief The magnified plane: `fractal` (the decode at 2^log_factor × `native`'s size) blended
/// with the bicubic upscale of `native`, then back-projected onto `native`, by kZoomAt2 or
/// kZoomAt4. The same on any `threads`.
PifsRaster zoom_filter(const PifsRaster& fractal, const PifsRaster& native, int log_factor, int threads = 1);

}  // namespace ifsforge
