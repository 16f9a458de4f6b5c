#pragma once
/// @file Step 2 of the seed's coding scheme for every candidate range cell of one quadtree level:
/// the best domain cell, isometry and quantised (s, o) by least squares (Eq. 29), and the flat
/// alternative (s = 0).
#include <cstdint>
#include <vector>

#include "ifsforge/core/progress.h"
#include "ifsforge/pifs/code.h"

namespace ifsforge {

/// @brief A padded plane in 8-bit levels (0..255 as floats), row-major.
struct PifsRaster {
  int width = 0, height = 0;
  std::vector<float> values;
  float* row(int y) { return values.data() + std::size_t(y) * width; }
  const float* row(int y) const { return values.data() + std::size_t(y) * width; }
};

/// @brief The two ways to code one range cell, with their collage errors (sum of squares).
struct PifsCandidate {
  PifsLeaf transform;  ///< best transform (s ≠ 0), valid when has_transform
  PifsLeaf flat;       ///< s = 0: the block's quantised mean
  double transform_error = 0, flat_error = 0;
  bool has_transform = false;
};

/// @brief Search effort: neighbours evaluated exactly and k-d tree leaves visited per query.
struct PifsSearch {
  int neighbours = 8;
  int max_leaves = 64;
};

/// @brief Candidates for every 2^log_size block of `plane` (padded), in raster order of blocks.
/// Parallel over block rows; the result does not depend on `threads`.
std::vector<PifsCandidate> search_level(const PifsCode& code, const PifsRaster& plane, int log_size,
                                        const PifsSearch& search, int threads);

}  // namespace ifsforge
