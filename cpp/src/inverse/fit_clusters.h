#pragma once
// The initial collages of the fits (2D and 3D): k-means clusters of the target's cells, whose
// boxes the maps' first copies cover (each part of the target is a copy of the whole, Eq. 41).
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "ifsforge/core/random.h"

namespace ifsforge {

/// The target's box and its clusters' boxes: mins in [0, D), maxes in [D, 2D).
template <int D>
struct Clusters {
  std::array<double, 2 * D> whole;
  std::vector<std::array<double, 2 * D>> parts;
  std::array<double, D> centroid{};             ///< of the whole target
  std::vector<std::array<double, D + 1>> mass;  ///< per part: centroid and cell count
};

template <int D>
double cluster_distance(const std::array<double, D>& a, const std::array<double, D>& b) {
  if constexpr (D == 2) {
    return std::hypot(a[0] - b[0], a[1] - b[1]);
  } else {
    double s = 0;
    for (int k = 0; k < D; ++k) s += (a[k] - b[k]) * (a[k] - b[k]);
    return std::sqrt(s);
  }
}

/// k-means of the cells' centres `pts` into n clusters (k-means++ start, seeded); boxes grow by
/// `cell` on their upper sides (centres to cell extents).
template <int D>
Clusters<D> cluster_boxes(const std::vector<std::array<double, D>>& pts, int n, double cell, Rng& rng) {
  using P = std::array<double, D>;
  std::vector<P> centres;
  centres.push_back(pts[static_cast<std::size_t>(rng.uniform() * pts.size())]);
  std::vector<double> d2(pts.size());
  while (static_cast<int>(centres.size()) < n) {
    double total = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      double best = std::numeric_limits<double>::infinity();
      for (const auto& c : centres) best = std::min(best, cluster_distance<D>(pts[i], c));
      d2[i] = best * best;
      total += d2[i];
    }
    double pick = rng.uniform() * total;
    std::size_t i = 0;
    while (i + 1 < pts.size() && (pick -= d2[i]) > 0) ++i;
    centres.push_back(pts[i]);
  }
  std::vector<int> label(pts.size());
  for (int it = 0; it < 20; ++it) {
    for (std::size_t i = 0; i < pts.size(); ++i) {
      double best = std::numeric_limits<double>::infinity();
      for (int c = 0; c < n; ++c) {
        const double d = cluster_distance<D>(pts[i], centres[c]);
        if (d < best) best = d, label[i] = c;
      }
    }
    std::vector<std::array<double, D + 1>> sum(n, std::array<double, D + 1>{});
    for (std::size_t i = 0; i < pts.size(); ++i) {
      for (int k = 0; k < D; ++k) sum[label[i]][k] += pts[i][k];
      sum[label[i]][D] += 1;
    }
    for (int c = 0; c < n; ++c)
      if (sum[c][D] > 0)
        for (int k = 0; k < D; ++k) centres[c][k] = sum[c][k] / sum[c][D];
  }
  const double inf = std::numeric_limits<double>::infinity();
  std::array<double, 2 * D> empty;
  for (int k = 0; k < D; ++k) empty[k] = inf, empty[D + k] = -inf;
  Clusters<D> out{empty, std::vector<std::array<double, 2 * D>>(n, empty), {},
                  std::vector<std::array<double, D + 1>>(n, std::array<double, D + 1>{})};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    auto& m = out.mass[label[i]];
    for (int k = 0; k < D; ++k) m[k] += pts[i][k], out.centroid[k] += pts[i][k] / pts.size();
    m[D] += 1;
  }
  for (auto& m : out.mass)
    if (m[D] > 0)
      for (int k = 0; k < D; ++k) m[k] /= m[D];
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (auto* b : {&out.whole, &out.parts[label[i]]})
      for (int k = 0; k < D; ++k) (*b)[k] = std::min((*b)[k], pts[i][k]), (*b)[D + k] = std::max((*b)[D + k], pts[i][k]);
  for (int c = 0; c < n; ++c) {
    auto& b = out.parts[c];
    if (b[0] > b[D])
      for (int k = 0; k < D; ++k) b[k] = b[D + k] = centres[c][k];
    for (int k = 0; k < D; ++k) b[D + k] += cell;
  }
  for (int k = 0; k < D; ++k) out.whole[D + k] += cell;
  return out;
}

/// The points `pts` each with its nearest cluster's centroid (`clusters.mass`): the k-means partition.
template <int D>
std::vector<std::vector<std::array<double, D>>> cluster_parts(const std::vector<std::array<double, D>>& pts,
                                                              const Clusters<D>& clusters) {
  std::vector<std::array<double, D>> centres(clusters.mass.size());
  for (std::size_t c = 0; c < centres.size(); ++c)
    for (int k = 0; k < D; ++k) centres[c][k] = clusters.mass[c][k];
  std::vector<std::vector<std::array<double, D>>> parts(centres.size());
  for (const auto& p : pts) {
    std::size_t nearest = 0;
    for (std::size_t c = 1; c < centres.size(); ++c)
      if (cluster_distance<D>(p, centres[c]) < cluster_distance<D>(p, centres[nearest])) nearest = c;
    parts[nearest].push_back(p);
  }
  return parts;
}

}  // namespace ifsforge
