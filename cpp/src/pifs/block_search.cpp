#include "ifsforge/pifs/block_search.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/code.h"

namespace ifsforge {
namespace {
constexpr int kLeafSize = 8;
}

bool block_feature(const float* block, long stride, int n, BlockFeature& out) {
  // n ≥ 4: 4×4 cells of n/4 pixels summed; n = 2: each pixel repeated over 2×2 cells.
  const int cell = std::max(1, n / 4);
  double mean = 0;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) {
      double sum = 0;
      if (n < 4) {
        sum = block[long(j * n / 4) * stride + i * n / 4];
      } else {
        for (int y = 0; y < cell; ++y) {
          const float* row = block + (long(j) * cell + y) * stride + long(i) * cell;
          for (int x = 0; x < cell; ++x) sum += row[x];
        }
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

namespace {

/// The top-left and top-right quadrant sums of every one of the 16 views of `f` (index
/// isometry·2 + negate). An isometry of the 4×4 grid moves whole quadrants as it moves the
/// cells of a 2×2 grid.
void view_quadrants(const BlockFeature& f, float q0[16], float q1[16]) {
  float quad[2][2];
  for (int b = 0; b < 2; ++b)
    for (int a = 0; a < 2; ++a) {
      const int o = b * 8 + a * 2;
      quad[b][a] = f[o] + f[o + 1] + f[o + 4] + f[o + 5];
    }
  for (int iso = 0; iso < 8; ++iso) {
    int a, b;
    isometry_map(iso, 2, 0, 0, a, b);
    const float tl = quad[b][a];
    isometry_map(iso, 2, 1, 0, a, b);
    const float tr = quad[b][a];
    q0[2 * iso] = tl;
    q1[2 * iso] = tr;
    q0[2 * iso + 1] = -tl;
    q1[2 * iso + 1] = -tr;
  }
}

int best_view(const float q0[16], const float q1[16]) {
  int best = 0;
  for (int v = 1; v < 16; ++v)
    if (q0[v] > q0[best] || (q0[v] == q0[best] && q1[v] > q1[best])) best = v;
  return best;
}

struct IsometryTables {
  int compose[8][8], inverse[8];
  IsometryTables() {
    BlockFeature index;
    for (int i = 0; i < kFeatureDim; ++i) index[i] = float(i);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const BlockFeature ab = transform_feature(transform_feature(index, a, false), b, false);
        for (int c = 0; c < 8; ++c)
          if (transform_feature(index, c, false) == ab) compose[a][b] = c;
      }
    for (int a = 0; a < 8; ++a)
      for (int c = 0; c < 8; ++c)
        if (compose[a][c] == 0) inverse[a] = c;
  }
};

const IsometryTables& tables() {
  static const IsometryTables t;
  return t;
}

constexpr int kTranspose = 4;  // the isometry that keeps the top-left quadrant in place

}  // namespace

int compose_isometry(int first, int then) { return tables().compose[first][then]; }
int inverse_isometry(int iso) { return tables().inverse[iso]; }

Orientation canonical_orientation(const BlockFeature& f) {
  float q0[16], q1[16];
  view_quadrants(f, q0, q1);
  const int v = best_view(q0, q1);
  return {v >> 1, (v & 1) != 0};
}

int near_canonical_orientations(const BlockFeature& f, float margin, Orientation out[16]) {
  float q0[16], q1[16];
  view_quadrants(f, q0, q1);
  const int best = best_view(q0, q1);
  int count = 0;
  out[count++] = {best >> 1, (best & 1) != 0};
  for (int v = 0; v < 16; ++v) {
    if (v == best || q0[v] < q0[best] - margin) continue;
    const int partner = compose_isometry(v >> 1, kTranspose) * 2 + (v & 1);
    if (q1[v] >= q1[partner] - margin) out[count++] = {v >> 1, (v & 1) != 0};
  }
  return count;
}

namespace {

FeatureTree::Point quantise(const BlockFeature& f) {
  FeatureTree::Point p;
  for (int i = 0; i < kFeatureDim; ++i) p[i] = std::int8_t(std::clamp(std::lround(f[i] * 127.f), -127L, 127L));
  return p;
}

/// Squared distance of two quantised features: integers, so SSE2 and the plain loop agree exactly.
int distance(const FeatureTree::Point& a, const FeatureTree::Point& b) {
#ifdef __SSE2__
  const __m128i va = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a.data()));
  const __m128i vb = _mm_loadu_si128(reinterpret_cast<const __m128i*>(b.data()));
  // Sign-extend the bytes to 16 bits (each byte into the high half, then shifted down).
  const __m128i zero = _mm_setzero_si128();
  const __m128i d_lo = _mm_sub_epi16(_mm_srai_epi16(_mm_unpacklo_epi8(zero, va), 8), _mm_srai_epi16(_mm_unpacklo_epi8(zero, vb), 8));
  const __m128i d_hi = _mm_sub_epi16(_mm_srai_epi16(_mm_unpackhi_epi8(zero, va), 8), _mm_srai_epi16(_mm_unpackhi_epi8(zero, vb), 8));
  __m128i sum = _mm_add_epi32(_mm_madd_epi16(d_lo, d_lo), _mm_madd_epi16(d_hi, d_hi));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(1, 0, 3, 2)));
  sum = _mm_add_epi32(sum, _mm_shuffle_epi32(sum, _MM_SHUFFLE(2, 3, 0, 1)));
  return _mm_cvtsi128_si32(sum);
#else
  int d = 0;
  for (int j = 0; j < kFeatureDim; ++j) {
    const int e = int(a[j]) - int(b[j]);
    d += e * e;
  }
  return d;
#endif
}

}  // namespace

FeatureTree::FeatureTree(const std::vector<BlockFeature>& points, std::vector<std::uint32_t> tags)
    : tags_(std::move(tags)) {
  points_.reserve(points.size());
  for (const BlockFeature& f : points) points_.push_back(quantise(f));
  if (!points_.empty()) {
    nodes_.reserve(4 * points_.size() / kLeafSize + 2);
    order_.resize(points_.size());
    std::iota(order_.begin(), order_.end(), 0);
    build(0, int(points_.size()));
    std::vector<Point> p(points_.size());
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
  if (end - begin > 4096 && stop_requested()) throw Cancelled();  // a large pool's build hears Ctrl-C
  const int index = int(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= kLeafSize) {
    nodes_[index].left = begin;
    nodes_[index].right = end;
    return index;
  }
  // Split the widest dimension (spread measured on at most 64 evenly spaced points) at its median.
  const int step = std::max(1, (end - begin) / 64);
  int dim = 0, widest = -1;
  for (int d = 0; d < kFeatureDim; ++d) {
    int lo = points_[order_[begin]][d], hi = lo;
    for (int i = begin + step; i < end; i += step) {
      const int v = points_[order_[i]][d];
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

void FeatureTree::nearest(const BlockFeature& query, int k, int max_leaves, std::vector<std::uint32_t>& out) const {
  out.clear();
  if (points_.empty()) return;
  const Point q = quantise(query);
  // Scratch reused across queries of a thread: a query allocates nothing.
  using Entry = std::pair<int, int>;  // (lower bound, node): min-heap by bound
  thread_local std::vector<Entry> queue;
  thread_local std::vector<std::pair<int, std::uint32_t>> best;  // max-heap of the k nearest
  queue.clear();
  best.clear();
  const auto later = [](const Entry& a, const Entry& b) { return a > b; };
  queue.push_back({0, 0});
  int leaves = 0;
  while (!queue.empty() && leaves < max_leaves) {
    std::pop_heap(queue.begin(), queue.end(), later);
    auto [bound, node] = queue.back();
    queue.pop_back();
    if (int(best.size()) == k && bound >= best.front().first) break;
    // Descend to a leaf, queueing the far sides.
    while (nodes_[node].dim >= 0) {
      const Node& n = nodes_[node];
      const int diff = int(q[n.dim]) - n.split;
      const int near = diff < 0 ? n.left : n.right, far = diff < 0 ? n.right : n.left;
      const int far_bound = bound + diff * diff;
      if (int(best.size()) < k || far_bound < best.front().first) {
        queue.push_back({far_bound, far});
        std::push_heap(queue.begin(), queue.end(), later);
      }
      node = near;
    }
    ++leaves;
    const Node& leaf = nodes_[node];
    for (int i = leaf.left; i < leaf.right; ++i) {
      const std::pair<int, std::uint32_t> entry{distance(q, points_[i]), tags_[i]};
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
