#pragma once
/// @file PIFS encoding of an image (seed 3.3.2.1, Steps 1-6) with rate control.
#include <cstddef>

#include "ifsforge/core/progress.h"
#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"
#include "ifsforge/core/image.h"

namespace ifsforge {

/// How the chroma of a YCbCr code is sampled: half size (4:2:0, Step 2), full size (4:4:4), or
/// automatic (full only where half-size chroma would cap a size target's quality).
enum class PifsChroma { Auto, Half, Full };
template <>
struct EnumNames<PifsChroma> {
  static constexpr const char* what = "chroma";
  static constexpr NamedValue<PifsChroma> values[] = {
      {PifsChroma::Auto, "auto"}, {PifsChroma::Half, "half"}, {PifsChroma::Full, "full"}};
};

struct PifsEncodeOptions {
  /// Range sizes (powers of two): the quadtree depths. min_block 0: with a size target and the
  /// residual layer, the residual's 8×8 block (at most max_block); else 2 when the size target
  /// is at least 1/kFineRatio of the raw image (or quality ≤ kFineQuality), else 4.
  int min_block = 0, max_block = 32;
  int s_bits = 5;                     ///< contrast bits (Eq. 29's s quantised, |s| ≤ 15/16)
  int dc_step = 1;                    ///< range-mean quantisation, 8-bit levels
  /// Rate control, first that is set wins: bytes (file size ≤ bytes), ratio (raw bytes /
  /// ratio), else quality (collage RMS threshold in 8-bit levels).
  std::size_t bytes = 0;
  double ratio = 0;
  double quality = kDefaultQuality;
  bool ycbcr = true;                  ///< RGB(A) as YCbCr (Steps 1-2), else R, G, B as they are
  /// YCbCr chroma sampling. Auto: 4:2:0, except under a size target where averaging the chroma
  /// 2×2 costs over kFullChromaShare of the squared error the 4:2:0 code's residual step
  /// foresees (and over kChromaErrorFloor): then 4:4:4 is coded too and the code nearer the
  /// image kept.
  PifsChroma chroma = PifsChroma::Auto;
  /// Under a size target, code what the fractal code misses as a DCT residual layer (residual.h).
  bool residual = true;
  PifsSearch search;
  int threads = 0;

  static constexpr double kDefaultQuality = 8.0;
  static constexpr double kFineRatio = 16.0, kFineQuality = 2.0;
  static constexpr double kFullChromaShare = 0.25, kChromaErrorFloor = 0.05;  // 8-bit levels²
};

/// @brief The PIFS code of `image` (1-4 channels, values in [0, 1], read as 8-bit levels).
/// InputError for an empty image, bad options or a size target below the smallest code.
PifsCode pifs_encode(const Image& image, const PifsEncodeOptions& options = {},
                     const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
