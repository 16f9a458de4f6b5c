#include "ifsforge/pifs/block_search.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <queue>

#include "ifsforge/pifs/code.h"

namespace ifsforge {
namespace {
constexpr int kLeafSize = 8;
}

bool block_feature(const float* block, long stride, int n, BlockFeature& out) {
  const int cell = n / 4;
  double mean = 0;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      double sum = 0;
      for (int y = 0; y < cell; ++y) {
        const float* row = block + (long(j) * cell + y) * stride + long(i) * cell;
        for (int x = 0; x < cell; ++x) sum += row[x];
      }
      out[j * 4 + i] = float(sum);
      mean += sum;
    }
  mean /= kFeatureDim;
  double norm = 0;
  for (float& v : out) {
    v = float(v - mean);
    norm += double(v) * v;
  }
  // Flat: below a quarter of an 8-bit level of deviation per pixel.
  if (norm <= 0.0625 * double(cell) * cell * cell * cell * kFeatureDim) return false;
  const float inv = float(1.0 / std::sqrt(norm));
  for (float& v : out) v *= inv;
  return true;
}

BlockFeature transform_feature(const BlockFeature& f, int iso, bool negate) {
  BlockFeature out;
  for (int v = 0; v < 4; ++v)
    for (int u = 0; u < 4; ++u) {
      int a, b;
      isometry_map(iso, 4, u, v, a, b);
      out[v * 4 + u] = negate ? -f[b * 4 + a] : f[b * 4 + a];
    }
  return out;
}

FeatureTree::FeatureTree(std::vector<BlockFeature> points, std::vector<std::uint32_t> tags)
    : points_(std::move(points)), tags_(std::move(tags)) {
  if (!points_.empty()) {
    nodes_.reserve(4 * points_.size() / kLeafSize + 2);
    order_.resize(points_.size());
    std::iota(order_.begin(), order_.end(), 0);
    build(0, int(points_.size()));
    std::vector<BlockFeature> p(points_.size());
    std::vector<std::uint32_t> t(points_.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      p[i] = points_[order_[i]];
      t[i] = tags_[order_[i]];
    }
    points_.swap(p);
    tags_.swap(t);
    order_.clear();
    order_.shrink_to_fit();
  }
}

int FeatureTree::build(int begin, int end) {
  // Builds over order_ (indices into points_); the points are permuted once at the end.
  const int index = int(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[index].left = begin;
    nodes_[index].right = end;
    return index;
  }
  // Split the widest dimension (spread measured on at most 64 evenly spaced points) at its median.
  const int step = std::max(1, (end - begin) / 64);
  int dim = 0;
  float widest = -1;
  for (int d = 0; d < kFeatureDim; ++d) {
    float lo = points_[order_[begin]][d], hi = lo;
    for (int i = begin + step; i < end; i += step) {
      const float v = points_[order_[i]][d];
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (hi - lo > widest) { widest = hi - lo; dim = d; }
  }
  const int mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
    return points_[a][dim] < points_[b][dim] || (points_[a][dim] == points_[b][dim] && a < b);
  });
  nodes_[index].dim = dim;
  nodes_[index].split = points_[order_[mid]][dim];
  const int left = build(begin, mid);
  const int right = build(mid, end);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

void FeatureTree::nearest(const BlockFeature& q, int k, int max_leaves, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (points_.empty()) return;
  // best: max-heap of (distance, tag) holding the k nearest so far.
  std::vector<std::pair<float, std::uint32_t>> best;
  using Entry = std::pair<float, int>;  // (lower bound, node)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  queue.push({0.f, 0});
  int leaves = 0;
  while (!queue.empty() && leaves < max_leaves) {
    auto [bound, node] = queue.top();
    queue.pop();
    if (int(best.size()) == k && bound >= best.front().first) break;
    // Descend to a leaf, queueing the far sides.
    while (nodes_[node].dim >= 0) {
      const Node& n = nodes_[node];
      const float diff = q[n.dim] - n.split;
      const int near = diff < 0 ? n.left : n.right, far = diff < 0 ? n.right : n.left;
      queue.push({bound + diff * diff, far});
      node = near;
    }
    ++leaves;
    const Node& leaf = nodes_[node];
    for (int i = leaf.left; i < leaf.right; ++i) {
      float d = 0;
      for (int j = 0; j < kFeatureDim; ++j) {
        const float e = q[j] - points_[i][j];
        d += e * e;
      }
      const std::pair<float, std::uint32_t> entry{d, tags_[i]};
      if (int(best.size()) < k) {
        best.push_back(entry);
        std::push_heap(best.begin(), best.end());
      } else if (entry < best.front()) {
        std::pop_heap(best.begin(), best.end());
        best.back() = entry;
        std::push_heap(best.begin(), best.end());
      }
    }
  }
  std::sort_heap(best.begin(), best.end());
  for (const auto& e : best) out.push_back(e.second);
}

}  // namespace ifsforge
