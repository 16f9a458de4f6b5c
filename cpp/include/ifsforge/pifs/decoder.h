#pragma once
/// @file PIFS decoding at any resolution (seed 3.3.2.2): Baharav's hierarchical decoding (the
/// coarsest level iterated to its fixed point, then one pass per doubling) and the iterative
/// deterministic decoding (DIA) at the output scale as the reference.
#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"
#include "ifsforge/core/image.h"

namespace ifsforge {

enum class PifsDecoder { Hierarchical, Iterative };
template <>
struct EnumNames<PifsDecoder> {
  static constexpr const char* what = "decoder";
  static constexpr NamedValue<PifsDecoder> values[] = {
      {PifsDecoder::Hierarchical, "hierarchical"},
      {PifsDecoder::Iterative, "iterative"}};
};

/// @brief What a magnified decode (scale above 1) returns: `hybrid` (the default) is the zoom
/// post-filter of zoom.h, tuned against bicubic upscaling of the 1× decode; `fractal` is the
/// plain fractal decode at the output scale.
enum class PifsZoom { Hybrid, Fractal };
template <>
struct EnumNames<PifsZoom> {
  static constexpr const char* what = "zoom";
  static constexpr NamedValue<PifsZoom> values[] = {{PifsZoom::Hybrid, "hybrid"}, {PifsZoom::Fractal, "fractal"}};
};

struct PifsDecodeOptions {
  double scale = 1.0;           ///< output size = image size × scale (rounded), when width = 0
  int width = 0, height = 0;    ///< explicit output size (both > 0)
  PifsDecoder decoder = PifsDecoder::Hierarchical;
  int iterations = 0;           ///< 0: kDefaultIterations (coarsest level, or every level for Iterative)
  bool deblock = true;          ///< smooth the two pixels either side of every range-block edge
  PifsZoom zoom = PifsZoom::Hybrid;  ///< above 1×: the zoom post-filter or the plain fractal decode
  int threads = 0;
};

/// @brief Iterations at the fixed-point level: |s| ≤ 15/16, but with the range mean fixed the
/// error falls by about the mean |s| per pass, so a dozen passes reach 8-bit precision.
constexpr int kDefaultIterations = 12;

/// @brief The image the code describes, at the requested size (RGB(A) for colour codes).
Image pifs_decode(const PifsCode& code, const PifsDecodeOptions& options = {});

/// @brief One plane decoded at scale 2^log_scale of its own size (padded size × 2^log_scale;
/// log_scale may be negative down to −min_log, lower scales are averaged down).
PifsRaster decode_plane(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsDecoder decoder,
                        int iterations, int threads);

}  // namespace ifsforge
