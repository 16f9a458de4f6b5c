#pragma once
/// @file Fast domain search (the seed's [179]): blocks reduced to normalised 4×4 features
/// (mean removed, unit norm), so the least-squares error of Eq. 29 falls as the features' distance
/// falls. Each feature is first turned to a canonical orientation (Fisher's classes: the
/// strongest quadrant top-left and positive), so the k-d tree holds one point per domain
/// instead of one per domain × isometry × sign, and a range asks once per plausible orientation.
#include <array>
#include <cstdint>
#include <vector>

namespace ifsforge {

constexpr int kFeatureDim = 16;
using BlockFeature = std::array<float, kFeatureDim>;

/// @brief The n×n block at `block` (row stride `stride`) pooled to 4×4 (n a multiple of 4, or 2:
/// each pixel repeated), mean removed, scaled to unit norm. Returns false for a flat block (no direction).
bool block_feature(const float* block, long stride, int n, BlockFeature& out);

/// @brief The feature of the same block seen through isometry `iso` (code.h) and sign.
BlockFeature transform_feature(const BlockFeature& f, int iso, bool negate);

/// @brief An isometry (code.h) with a sign: the 16 ways one block is compared with another.
struct Orientation {
  int isometry = 0;
  bool negate = false;
};

/// @brief The orientation that makes `f` canonical: among its 16 views, the one whose top-left
/// quadrant sum is largest, then whose top-right quadrant sum is largest.
Orientation canonical_orientation(const BlockFeature& f);

/// @brief Every orientation whose view of `f` is canonical up to `margin` in those two quadrant
/// sums (the canonical one first): a range queries each, so a near tie that turned its domain the
/// other way is still found. Returns how many were written (1..16).
int near_canonical_orientations(const BlockFeature& f, float margin, Orientation out[16]);

/// @brief The isometry that applies `first`, then `then` (as transform_feature composes).
int compose_isometry(int first, int then);
/// @brief The isometry that undoes `iso`.
int inverse_isometry(int iso);

/// @brief A k-d tree of domain features, each with a 32-bit tag and its block's norm
/// ‖d − mean_d‖; approximate best-bin-first queries ranked by the least-squares error of Eq. 29.
/// Points are held quantised to 8 bits (a unit feature's components ×127): a quarter of the
/// memory, and integer distances, exact and the same on every instruction set.
class FeatureTree {
 public:
  using Point = std::array<std::int8_t, kFeatureDim>;
  FeatureTree() = default;
  FeatureTree(const std::vector<BlockFeature>& points, std::vector<std::uint32_t> tags, std::vector<float> norms);
  /// @brief The `count` (≤ 16) views `queries` of one range of norm `norm` searched together
  /// (one queue, one list, at most `max_leaves` leaves in all): up to `k` results, least
  /// estimated error first, each tag << 4 | the index of the view that found it. The estimate
  /// is the error fraction of Eq. 29 with |s| ≤ s_max from the features' cosine and the norms'
  /// ratio, so a domain too flat to reach the range ranks low however alike their shapes.
  /// Deterministic: the same query always gives the same answer.
  void nearest(const BlockFeature* queries, int count, float norm, float s_max, int k, int max_leaves,
               std::vector<std::uint64_t>& out) const;
  bool empty() const { return points_.empty(); }

 private:
  struct Node {
    int dim = -1;       ///< split dimension, -1 for a leaf
    int split = 0;
    int left = 0, right = 0;  ///< children (inner) or [left, right) point range (leaf)
  };
  int build(int begin, int end);
  std::vector<Point> points_;
  std::vector<std::uint32_t> tags_;
  std::vector<float> norms_;
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

}  // namespace ifsforge
