#pragma once
/// @file A partitioned IFS code (seed 3.3.2, Definitions 14-16): per image plane, the quadtree
/// leaves (range cells) with their domain cell, isometry and the quantised Eq. 29 parameters.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "ifsforge/core/names.h"

namespace ifsforge {

/// @brief One range cell and its transform. Eq. 29, r = s·φ(d) + o, is stored with o expressed
/// through the range mean (o = mean_r − s·mean_φ(d)): the decorrelated form, so `dc` is the
/// block's mean and s = 0 is a flat block with no domain at all.
struct PifsLeaf {
  std::uint16_t x = 0, y = 0;     ///< top-left corner in the padded plane, pixels
  std::uint8_t log_size = 0;      ///< range size 2^log_size
  std::int8_t s = 0;              ///< quantised contrast: s = s_q / 2^(s_bits−1), |s| < 1
  std::uint8_t dc = 0;            ///< quantised range mean: dc · dc_step, in 8-bit levels
  std::uint8_t isometry = 0;      ///< 0..7 (bit 0 flip x, bit 1 flip y, bit 2 transpose)
  std::uint16_t dx = 0, dy = 0;   ///< domain cell index on the domain grid (step = range size)
};

/// @brief The residual layer of a plane (pifs/residual.h): quantised 8×8 DCT coefficients of
/// what the decoded fractal code misses, 64 per block in zigzag order, blocks in raster order.
struct PifsResidual {
  int step = 0;  ///< quantisation step in 1/kResidualStepScale levels (residual.h); 0: no residual
  std::vector<std::int16_t> coefficients;
};

/// @brief One independently coded plane (Y, Cb, Cr, alpha or gray).
struct PifsPlane {
  int width = 0, height = 0;       ///< the plane's own size (chroma: half the image, rounded up)
  std::vector<PifsLeaf> leaves;    ///< in coding order: top blocks in raster order, quadtree depth first
  PifsResidual residual;
};

/// @brief Colour handling of a code (the seed's Steps 1-2 for colour textures).
/// YCbCr420 halves the chroma (Step 2); YCbCr444 keeps it at full size, for budgets rich enough
/// that half-size chroma would cap the quality.
enum class PifsColor : std::uint8_t { Direct = 0, YCbCr420 = 1, YCbCr444 = 2 };
template <>
struct EnumNames<PifsColor> {
  static constexpr const char* what = "color coding";
  static constexpr NamedValue<PifsColor> values[] = {
      {PifsColor::Direct, "direct"},
      {PifsColor::YCbCr420, "ycbcr420"},
      {PifsColor::YCbCr444, "ycbcr444"}};
};

struct PifsCode {
  int width = 0, height = 0, channels = 0;  ///< the image: 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA
  PifsColor color = PifsColor::Direct;
  int min_log = 2, max_log = 5;             ///< range sizes 2^min_log .. 2^max_log (q_max, q_min)
  int s_bits = 5;                           ///< bits of the quantised contrast s (Eq. 29)
  int dc_step = 1;                          ///< quantisation step of the range mean, 8-bit levels
  std::vector<PifsPlane> planes;

  /// @brief Whether the planes are Y, Cb, Cr [, alpha] (else one plane per channel).
  bool ycc() const { return channels >= 3 && (color == PifsColor::YCbCr420 || color == PifsColor::YCbCr444); }
  /// @brief Whether plane k is stored at half size (4:2:0 chroma).
  bool halved(std::size_t k) const { return color == PifsColor::YCbCr420 && channels >= 3 && (k == 1 || k == 2); }
  /// @brief The padded plane size: a multiple of the largest range block.
  int padded(int size) const { const int b = 1 << max_log; return (size + b - 1) / b * b; }
  double s_value(int q) const { return double(q) / double(1 << (s_bits - 1)); }
  int s_limit() const { return (1 << (s_bits - 1)) - 1; }
};

/// @brief The 8 square isometries: range pixel (u, v) reads domain pixel (a, b) of an n×n block.
inline void isometry_map(int iso, int n, int u, int v, int& a, int& b) {
  a = (iso & 4) ? v : u;
  b = (iso & 4) ? u : v;
  if (iso & 1) a = n - 1 - a;
  if (iso & 2) b = n - 1 - b;
}

/// @brief Isometry as a linear walk: domain offset of (u, v) = origin + u·du + v·dv (row stride
/// `stride`), for an n×n block starting at offset 0.
inline void isometry_walk(int iso, int n, long stride, long& origin, long& du, long& dv) {
  long ax = 1, ay = stride;  // a moves along x, b along y
  long a0 = 0, b0 = 0;
  long sa = 1, sb = 1;
  if (iso & 1) { a0 = n - 1; sa = -1; }
  if (iso & 2) { b0 = n - 1; sb = -1; }
  origin = a0 * ax + b0 * ay;
  if (iso & 4) { du = sb * ay; dv = sa * ax; } else { du = sa * ax; dv = sb * ay; }
}

}  // namespace ifsforge
