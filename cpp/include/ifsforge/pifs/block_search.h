#pragma once
/// @file Fast domain search (the seed's [179]): blocks reduced to normalised 4×4 features
/// (mean removed, unit norm), so the least-squares error of Eq. 29 falls as the features' distance
/// falls; a k-d tree over every domain × isometry × sign answers nearest-neighbour queries.
#include <array>
#include <cstdint>
#include <vector>

namespace ifsforge {

constexpr int kFeatureDim = 16;
using BlockFeature = std::array<float, kFeatureDim>;

/// @brief The n×n block at `block` (row stride `stride`) pooled to 4×4 (n a multiple of 4),
/// mean removed, scaled to unit norm. Returns false for a flat block (no direction).
bool block_feature(const float* block, long stride, int n, BlockFeature& out);

/// @brief The feature of the same block seen through isometry `iso` (code.h) and sign.
BlockFeature transform_feature(const BlockFeature& f, int iso, bool negate);

/// @brief A k-d tree of features, each with a 32-bit tag; approximate best-bin-first queries.
class FeatureTree {
 public:
  FeatureTree(std::vector<BlockFeature> points, std::vector<std::uint32_t> tags);
  /// @brief Up to `k` tags of the nearest points, nearest first, visiting at most `max_leaves`
  /// leaves. Deterministic: the same query always gives the same answer.
  void nearest(const BlockFeature& q, int k, int max_leaves, std::vector<std::uint32_t>& out) const;
  bool empty() const { return points_.empty(); }

 private:
  struct Node {
    int dim = -1;       ///< split dimension, -1 for a leaf
    float split = 0;
    int left = 0, right = 0;  ///< children (inner) or [left, right) point range (leaf)
  };
  int build(int begin, int end);
  std::vector<BlockFeature> points_;
  std::vector<std::uint32_t> tags_;
  std::vector<Node> nodes_;
  std::vector<int> order_;
};

}  // namespace ifsforge
