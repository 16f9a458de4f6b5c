#include "ifsforge/pifs/block_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/code.h"

namespace ifsforge {
namespace {
// Leaves of 16..32 points: scanned four at a time, so fewer, larger leaves cost less than the
// queue work of finer ones.
constexpr int kLeafSize = 32;
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

/// Squared distances of `count` quantised features from `q`, into `out`: integers, so SSE2 and
/// the plain loop agree exactly. SSE2 takes four at a time and sums their lanes together.
void distances(const FeatureTree::Point* p, int count, const FeatureTree::Point& q, int* out) {
  int i = 0;
#ifdef __SSE2__
  // Sign-extend bytes to 16 bits: each byte into the high half, then shifted down.
  const __m128i zero = _mm_setzero_si128();
  const __m128i vq = _mm_loadu_si128(reinterpret_cast<const __m128i*>(q.data()));
  const __m128i q_lo = _mm_srai_epi16(_mm_unpacklo_epi8(zero, vq), 8), q_hi = _mm_srai_epi16(_mm_unpackhi_epi8(zero, vq), 8);
  const auto squares = [&](const FeatureTree::Point& a) {
    const __m128i va = _mm_loadu_si128(reinterpret_cast<const __m128i*>(a.data()));
    const __m128i d_lo = _mm_sub_epi16(_mm_srai_epi16(_mm_unpacklo_epi8(zero, va), 8), q_lo);
    const __m128i d_hi = _mm_sub_epi16(_mm_srai_epi16(_mm_unpackhi_epi8(zero, va), 8), q_hi);
    return _mm_add_epi32(_mm_madd_epi16(d_lo, d_lo), _mm_madd_epi16(d_hi, d_hi));
  };
  for (; i + 4 <= count; i += 4) {
    const __m128i a = squares(p[i]), b = squares(p[i + 1]), c = squares(p[i + 2]), d = squares(p[i + 3]);
    const __m128i ab = _mm_add_epi32(_mm_unpacklo_epi32(a, b), _mm_unpackhi_epi32(a, b));  // a01 b01 a23 b23
    const __m128i cd = _mm_add_epi32(_mm_unpacklo_epi32(c, d), _mm_unpackhi_epi32(c, d));
    const __m128i sum = _mm_add_epi32(_mm_unpacklo_epi64(ab, cd), _mm_unpackhi_epi64(ab, cd));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out + i), sum);
  }
#endif
  for (; i < count; ++i) {
    int d = 0;
    for (int j = 0; j < kFeatureDim; ++j) {
      const int e = int(p[i][j]) - int(q[j]);
      d += e * e;
    }
    out[i] = d;
  }
}

}  // namespace

FeatureTree::FeatureTree(const std::vector<BlockFeature>& points, std::vector<std::uint32_t> tags, std::vector<float> norms)
    : tags_(std::move(tags)), norms_(std::move(norms)) {
  points_.reserve(points.size());
  for (const BlockFeature& f : points) points_.push_back(quantise(f));
  if (!points_.empty()) {
    nodes_.reserve(4 * points_.size() / kLeafSize + 2);
    order_.resize(points_.size());
    std::iota(order_.begin(), order_.end(), 0);
    build(0, int(points_.size()));
    std::vector<Point> p(points_.size());
    std::vector<std::uint32_t> t(points_.size());
    std::vector<float> e(points_.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      p[i] = points_[order_[i]];
      t[i] = tags_[order_[i]];
      e[i] = norms_[order_[i]];
    }
    points_.swap(p);
    tags_.swap(t);
    norms_.swap(e);
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

namespace {
// Two quantised unit features at squared distance D have cosine c = 1 − D / kUnit2.
constexpr float kUnit2 = 2.f * 127.f * 127.f;
}  // namespace

void FeatureTree::nearest(const BlockFeature* queries, int count, float norm, float s_max, int k, int max_leaves,
                          std::vector<std::uint64_t>& out) const {
  out.clear();
  if (points_.empty()) return;
  Point qs[16];
  for (int v = 0; v < count; ++v) qs[v] = quantise(queries[v]);
  struct Entry {
    int bound, node, view;
    bool operator>(const Entry& o) const {
      return bound != o.bound ? bound > o.bound : node != o.node ? node > o.node : view > o.view;
    }
  };
  // Scratch reused across queries of a thread: a query allocates nothing.
  thread_local std::vector<Entry> queue;
  thread_local std::vector<std::pair<float, std::uint64_t>> best;  // max-heap of the k best
  queue.clear();
  best.clear();
  const float inv_norm = 1.f / norm;
  const auto later = [](const Entry& a, const Entry& b) { return a > b; };
  // Squared distances from `reject` on cannot enter the list: their error with s unbounded,
  // 1 − c², already reaches the worst kept one (set once the list is full).
  int reject = std::numeric_limits<int>::max();
  const auto tighten = [&] {
    const float worst = best.front().first;
    reject = worst >= 1.f ? std::numeric_limits<int>::max() : int((1.f - std::sqrt(1.f - worst)) * kUnit2) + 2;
  };
  for (int v = 0; v < count; ++v) queue.push_back({0, 0, v});
  int leaves = 0;
  while (!queue.empty() && leaves < max_leaves) {
    std::pop_heap(queue.begin(), queue.end(), later);
    auto [bound, node, view] = queue.back();
    queue.pop_back();
    if (bound >= reject) break;
    // Descend to a leaf, queueing the far sides.
    const Point& q = qs[view];
    while (nodes_[node].dim >= 0) {
      const Node& n = nodes_[node];
      const int diff = int(q[n.dim]) - n.split;
      const int near = diff < 0 ? n.left : n.right, far = diff < 0 ? n.right : n.left;
      const int far_bound = bound + diff * diff;
      if (far_bound < reject) {
        queue.push_back({far_bound, far, view});
        std::push_heap(queue.begin(), queue.end(), later);
      }
      node = near;
    }
    ++leaves;
    const Node& leaf = nodes_[node];
    int dist_of[kLeafSize];
    distances(&points_[leaf.left], leaf.right - leaf.left, q, dist_of);
    for (int i = leaf.left; i < leaf.right; ++i) {
      const int dist = dist_of[i - leaf.left];
      if (dist >= reject) continue;
      const float c = 1.f - float(dist) * (1.f / kUnit2);
      if (c <= 0) continue;
      // The error over ‖r‖²: 1 − c² at the best s = c/ρ, else at s = s_max (ρ = ‖d‖ / ‖r‖).
      const float rho = norms_[i] * inv_norm;
      const float f = c <= s_max * rho ? 1.f - c * c : 1.f - 2.f * s_max * rho * c + s_max * s_max * rho * rho;
      const std::pair<float, std::uint64_t> entry{f, std::uint64_t(tags_[i]) << 4 | std::uint64_t(view)};
      if (int(best.size()) < k) {
        best.push_back(entry);
        std::push_heap(best.begin(), best.end());
        if (int(best.size()) == k) tighten();
      } else if (entry < best.front()) {
        std::pop_heap(best.begin(), best.end());
        best.back() = entry;
        std::push_heap(best.begin(), best.end());
        tighten();
      }
    }
  }
  std::sort_heap(best.begin(), best.end());
  for (const auto& e : best) out.push_back(e.second);
}

}  // namespace ifsforge
