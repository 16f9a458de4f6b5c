#pragma once
/// @file Step 2 of the seed's coding scheme for every candidate range cell of one quadtree level:
/// the best domain cell, isometry and quantised (s, o) by least squares (Eq. 29), and the flat
/// alternative (s = 0).
#include <cstdint>
#include <vector>

#include "ifsforge/core/names.h"
#include "ifsforge/core/progress.h"
#include "ifsforge/pifs/block_search.h"
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

/// @brief How domains are found: the feature tree (the default), or every domain under every
/// isometry fitted exactly (the reference the tree's loss is measured against; slow).
enum class PifsDomainSearch : std::uint8_t { Tree = 0, Exhaustive = 1 };
template <>
struct EnumNames<PifsDomainSearch> {
  static constexpr const char* what = "domain search";
  static constexpr NamedValue<PifsDomainSearch> values[] = {
      {PifsDomainSearch::Tree, "tree"},
      {PifsDomainSearch::Exhaustive, "exhaustive"}};
};

/// @brief Search effort: domains fitted exactly per range (those of least estimated error; more
/// for ranges above 4×4, whose feature pools the block), k-d tree leaves a range may visit (all
/// of them from an RMS of full_effort_rms 8-bit levels, proportionally fewer below, at least
/// kMinLeaves), and how near a tie (in quadrant sums of unit features) still adds another
/// orientation of the range to its query.
struct PifsSearch {
  PifsDomainSearch mode = PifsDomainSearch::Tree;
  int neighbours = 4, pooled_neighbours = 8;
  int max_leaves = 64;
  double full_effort_rms = 16;
  float orientation_margin = 0.3f;
  static constexpr int kMinLeaves = 4;
};

/// @brief φ of Eq. 29 for every domain at once: the plane averaged 2×2, so the 2r×2r domain at
/// (x, y) is the r×r block at (x/2, y/2) of this raster.
PifsRaster half_plane(const PifsRaster& padded, int threads = 1, const ProgressCallback& progress = nullptr);

/// @brief Rows [begin, end) of half_plane(padded) written into `half` (padded.width / 2 ×
/// padded.height / 2); rows may be made in any order, side by side.
void half_rows(const PifsRaster& padded, PifsRaster& half, int begin, int end);

/// @brief The domain pool of one plane for ranges of 2^log_size: each domain's energy
/// Σ(d − mean_d)² (of its φ) and a tree of its canonical feature (with √energy, so the tree
/// ranks by Eq. 29's error, |s| < 1 included), shared read-only by the threads that search it.
struct PifsDomains {
  int log_size = 0;
  int nx = 0, ny = 0;           ///< domains across and down (domain_count)
  std::vector<double> energy;   ///< per domain, row-major
  FeatureTree tree;             ///< tag: domain index << 4 | canonical isometry << 1 | sign
};

/// @brief The pool for `half` = half_plane(padded plane of `padded_width` × `padded_height`);
/// without `with_tree` only the energies (the exhaustive search needs no tree).
PifsDomains domain_pool(const PifsRaster& half, int padded_width, int padded_height, int log_size,
                        bool with_tree = true);

/// @brief Candidates of the blocks in block row `row` of the padded plane, in column order,
/// written to `out` (one per block). Depends on nothing but its arguments.
void search_row(const PifsCode& code, const PifsRaster& plane, const PifsRaster& half, const PifsDomains& domains,
                const PifsSearch& search, int row, PifsCandidate* out);

}  // namespace ifsforge
