#pragma once
/// @file The orbit step of a 2D or 3D affine system (the walk of model/orbit.h) with the maps'
/// coefficients held in place, each map applied in AffineMap::apply's order: the attractor
/// samples (ifs.cpp) and their extent on several cores (attractor_extent.cpp) walk the same
/// points, bit for bit.
#include <cmath>
#include <cstdint>
#include <vector>

#include "ifsforge/core/random.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/orbit.h"

namespace ifsforge::affine_walk {

template <int N>
class Walker {
 public:
  explicit Walker(const Ifs& ifs) : a_(ifs.size() * N * N), b_(ifs.size() * N) {
    for (std::size_t i = 0; i < ifs.size(); ++i)
      for (int r = 0; r < N; ++r) {
        b_[i * N + r] = ifs.map(i).b(r);
        for (int c = 0; c < N; ++c) a_[(i * N + r) * N + c] = ifs.map(i).a(r, c);
      }
  }

  /// The next map from the chain, then p = w_map(p).
  void step(const MapChain& chain, Rng& rng, std::uint32_t& map, Point& p) const {
    map = chain.next(map, rng.next());
    const double *m = a_.data() + map * N * N, *t = b_.data() + map * N;
    double q[N];
    for (int r = 0; r < N; ++r) {
      double v = t[r];
      for (int c = 0; c < N; ++c) v += m[r * N + c] * p[c];
      q[r] = v;
    }
    for (int r = 0; r < N; ++r) p[r] = q[r];
  }

  static bool finite(const Point& p) {
    bool ok = true;
    for (int c = 0; c < N; ++c) ok = ok && std::isfinite(p[c]);
    return ok;
  }

 private:
  std::vector<double> a_, b_;
};

/// Where every walk starts: the system's start point, its coordinates past N zero (as after
/// Orbit's first step).
inline Point start(const Ifs& ifs, int n) {
  Point p = ifs.start_point();
  for (std::size_t c = static_cast<std::size_t>(n); c < p.size(); ++c) p[c] = 0.0;
  return p;
}

/// Steps before the first sample: the walk settles onto the attractor.
constexpr std::size_t kSettle = 100;

}  // namespace ifsforge::affine_walk
