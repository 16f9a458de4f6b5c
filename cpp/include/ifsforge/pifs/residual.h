#pragma once
/// @file The residual layer of a PIFS code: what the fractal code's decoded plane still misses,
/// as an 8×8 DCT per block, uniformly quantised and range coded with context models. It is
/// defined on the plane's native pixel grid; at finer scales it is magnified by Catmull-Rom
/// interpolation (smooth across the blocks' edges), at coarser ones averaged down, so the decoder
/// keeps decoding at any resolution.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "ifsforge/pifs/code.h"
#include "ifsforge/pifs/domain_search.h"

namespace ifsforge {

constexpr int kResidualBlock = 8;
/// Step units: the quantisation step is stored in 1/kResidualStepScale of an 8-bit level.
constexpr int kResidualStepScale = 16;

/// @brief The quantised coefficients of `target − decoded` (both at the plane's native size,
/// `width`×`height` pixels read from rasters at least that large) for `step` (8-bit levels).
/// A step too coarse to keep any coefficient (or beyond the largest step) gives an empty residual;
/// one below the smallest step is raised to it.
PifsResidual residual_quantise(const PifsRaster& target, const PifsRaster& decoded, int width, int height,
                               double step);

/// residual_quantise cut into rows of blocks, each quantised on its own (any thread, any order,
/// the same coefficients), so one plane's residual can keep several threads busy; the rows can
/// also be entropy coded one by one as they come (encode_residual's bytes, row by row).
class PifsResidualRows {
 public:
  PifsResidualRows(int width, int height, double step);
  ~PifsResidualRows();
  /// @brief The number of block rows: fixed by the plane, never by the thread count.
  int rows() const { return by_; }
  /// @brief Quantises block row `row` of `target − decoded`.
  void quantise(int row, const PifsRaster& target, const PifsRaster& decoded);
  /// @brief Entropy codes block row `row`, once it is quantised; rows are coded in order (only
  /// the coded size is kept: encode_residual writes the bytes).
  void code(int row);
  /// @brief The residual once every row is quantised (empty when no coefficient is nonzero);
  /// `coded_size`, when given, receives its encode_residual size (every row coded first).
  PifsResidual finish(std::size_t* coded_size = nullptr);
  class Coder;

 private:
  int width_, height_, q_ = 0, bx_ = 0, by_ = 0;
  PifsResidual residual_;
  std::vector<std::uint8_t> nonzero_;  ///< per block row: any coefficient kept
  std::unique_ptr<Coder> coder_;
};

/// @brief The range-coded bytes of a residual of a `width`×`height` plane (empty for none).
std::vector<std::uint8_t> encode_residual(const PifsResidual& residual, int width, int height);

/// @brief The residual from its bytes; InputError naming `where` when truncated or corrupt.
PifsResidual decode_residual(int step, int width, int height, const std::uint8_t* data, std::size_t size,
                             const std::string& where);

/// @brief Adds the residual of a `width`×`height` plane to `raster`, that plane decoded at scale
/// 2^log_scale (pixels beyond the raster are dropped).
void add_residual(const PifsResidual& residual, int width, int height, int log_scale, PifsRaster& raster,
                  int threads = 1);

}  // namespace ifsforge
