// The model: maps, parameters, layouts, systems and their analysis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <cmath>
#include <random>

#include "ifsforge/core/default_threads.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/error.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/linear_algebra.h"
#include "ifsforge/model/map_params.h"

using namespace ifsforge;

namespace {

AffineMap random_map(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> a(n * n), b(n);
  for (auto& v : a) v = u(rng);
  for (auto& v : b) v = u(rng);
  return AffineMap(n, a, b);
}

Ifs plain_sierpinski() {
  std::vector<AffineMap> maps;
  for (auto [x, y] : {std::pair{0.0, 0.0}, {0.5, 0.0}, {0.25, 0.5}})
    maps.emplace_back(2, std::vector<double>{0.5, 0, 0, 0.5}, std::vector<double>{x, y});
  return Ifs("sierpinski", ChannelLayout("xy"), maps, {1, 1, 1});
}

}  // namespace

TEST(SampleExtent, TheSameBitsAsOneScanOnAnyNumberOfThreads) {
  // The walk cut into pieces walked side by side (each guessed, then checked against the piece
  // before) or, where a guess misses (a slow contraction), walked on one core: the extent is
  // the scan's, bit for bit, and so is the first of equal values.
  std::mt19937 rng(11);
  std::vector<Ifs> systems{plain_sierpinski()};
  const Ifs fern("fern", ChannelLayout("xy"),
                 {AffineMap(2, {0, 0, 0, 0.16}, {0, 0}), AffineMap(2, {0.85, 0.04, -0.04, 0.85}, {0, 1.6}),
                  AffineMap(2, {0.2, -0.26, 0.23, 0.22}, {0, 1.6}), AffineMap(2, {-0.15, 0.28, 0.26, 0.24}, {0, 0.44})},
                 {0.01, 0.85, 0.07, 0.07});
  systems.push_back(fern);
  for (int n : {2, 3})
    for (double scale : {0.6, 0.97}) {  // 0.97: slow, the guesses may not meet
      std::vector<AffineMap> maps;
      for (int k = 0; k < 3; ++k) {
        const AffineMap m = random_map(rng, n);
        std::vector<double> a(n * n), b(n);
        for (int r = 0; r < n; ++r) {
          b[r] = m.b(r);
          for (int c = 0; c < n; ++c) a[r * n + c] = m.a(r, c) * scale / (n * 1.0);
        }
        maps.emplace_back(n, a, b);
      }
      systems.emplace_back("random", ChannelLayout(n == 2 ? "xy" : "xyz"), maps, std::vector<double>{1, 2, 3});
    }
  for (const Ifs& ifs : systems) {
    const int k = ifs.dim();
    for (std::size_t count : {std::size_t(1) << 15, (std::size_t(1) << 16) + 3}) {
      std::vector<double> lo(k, INFINITY), hi(k, -INFINITY);
      sample_attractor(ifs, count, 0xB0B5, [&](const Point& p) {
        for (int c = 0; c < k; ++c) {
          lo[c] = std::min(lo[c], p[c]);
          hi[c] = std::max(hi[c], p[c]);
        }
      });
      for (int threads = 1; threads <= 4; ++threads) {
        std::vector<double> l(k), h(k);
        sample_extent(ifs, count, 0xB0B5, k, [k](const Point& p, double* v) { std::copy(p.begin(), p.begin() + k, v); },
                      l.data(), h.data(), threads);
        EXPECT_EQ(std::memcmp(l.data(), lo.data(), k * sizeof(double)), 0) << ifs.name() << " threads " << threads;
        EXPECT_EQ(std::memcmp(h.data(), hi.data(), k * sizeof(double)), 0) << ifs.name() << " threads " << threads;
      }
    }
  }
}

TEST(AffineMap, Eq8And9EqualsTheLargestSingularValue) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const AffineMap m = random_map(rng, 2);
    EXPECT_NEAR(m.contraction_factor(), la::spectral_norm(la::block(m, 2), 2), 1e-12);
  }
  // A rotation by 30 degrees scaled by 0.6 contracts by exactly 0.6.
  const double c = 0.6 * std::cos(M_PI / 6), s = 0.6 * std::sin(M_PI / 6);
  EXPECT_NEAR(contraction_factor_2d(c, -s, s, c), 0.6, 1e-15);
  // diag(0.3, 0.7, 0.5) in 3D: the largest scale.
  EXPECT_NEAR(AffineMap(3, {0.3, 0, 0, 0, 0.7, 0, 0, 0, 0.5}, {1, 2, 3}).contraction_factor(), 0.7, 1e-12);
}

TEST(AffineMap, ComposedWithItsInverseIsTheIdentity) {
  std::mt19937 rng(11);
  for (int n = 1; n <= kMaxDim; ++n) {
    const AffineMap m = random_map(rng, n);
    const AffineMap id = m.compose(*m.inverse());
    for (int r = 0; r < n; ++r) {
      EXPECT_NEAR(id.b(r), 0.0, 1e-9);
      for (int c = 0; c < n; ++c) EXPECT_NEAR(id.a(r, c), r == c ? 1.0 : 0.0, 1e-9) << "n=" << n;
    }
  }
  EXPECT_FALSE(AffineMap(2, {0, 0, 0, 0.16}, {0, 0}).inverse());  // the fern's stem is singular
}

TEST(AffineMap, FixedPointIsFixed) {
  std::mt19937 rng(3);
  for (int n = 2; n <= 6; ++n) {
    const AffineMap m = random_map(rng, n);
    const auto p = m.fixed_point();
    ASSERT_TRUE(p);
    const Point q = m(*p);
    for (int c = 0; c < n; ++c) EXPECT_NEAR(q[c], (*p)[c], 1e-9);
  }
  const auto corner = plain_sierpinski().map(1).fixed_point();
  EXPECT_DOUBLE_EQ((*corner)[0], 1.0);
  EXPECT_DOUBLE_EQ((*corner)[1], 0.0);
  EXPECT_FALSE(AffineMap(2, {1, 0, 0, 0.5}, {1, 0}).fixed_point());  // a translation along x
}

TEST(MapParams, RoundTripThroughTheMatrix) {
  std::mt19937 rng(5);
  for (int n : {2, 3})
    for (int trial = 0; trial < 100; ++trial) {
      const AffineMap m = random_map(rng, n);
      const AffineMap back = map_from_params(params_from_map(m, n));
      for (int r = 0; r < n; ++r) {
        EXPECT_NEAR(back.b(r), m.b(r), 1e-12);
        for (int c = 0; c < n; ++c) EXPECT_NEAR(back.a(r, c), m.a(r, c), 1e-9) << "n=" << n;
      }
    }
  // Degenerate: the fern's stem keeps its matrix.
  const AffineMap stem(2, {0, 0, 0, 0.16}, {0, 0});
  const AffineMap back = map_from_params(params_from_map(stem, 2));
  EXPECT_NEAR(back.a(1, 1), 0.16, 1e-12);
  EXPECT_NEAR(back.a(0, 0), 0.0, 1e-12);
}

TEST(MapParams, Eq5) {
  MapParams p;
  p.scale = {0.5, 0.25, 1};
  p.rotation = {90, 90, 0};
  p.translation = {1, 2, 0};
  const AffineMap m = map_from_params(p);
  EXPECT_NEAR(m.a(0, 0), 0.0, 1e-15);
  EXPECT_NEAR(m.a(0, 1), -0.25, 1e-15);
  EXPECT_NEAR(m.a(1, 0), 0.5, 1e-15);
  EXPECT_NEAR(m.a(1, 1), 0.0, 1e-15);
  EXPECT_EQ(m.b(1), 2.0);
}

TEST(ChannelLayout, NamesAndErrors) {
  ChannelLayout l("xyz+rgb+k");
  EXPECT_EQ(l.dim(), 7);
  EXPECT_EQ(l.spatial_dims(), 3);
  EXPECT_EQ(l.index("g"), 4);
  EXPECT_EQ(l.primitive_index(), 6);
  EXPECT_EQ(ChannelLayout("xy+rgba").alpha_index(), 5);
  EXPECT_THROW(ChannelLayout("uv"), InputError);
  EXPECT_THROW(ChannelLayout("xy+rgb+hsi"), InputError);
  EXPECT_THROW(ChannelLayout("xyz+rgba+gray+alpha"), InputError);
}

TEST(Ifs, Classification) {
  EXPECT_EQ(plain_sierpinski().classify(), Classification::Hyperbolic);
  EXPECT_DOUBLE_EQ(plain_sierpinski().contraction_ratio(), 0.5);
  // One expanding map used rarely: contractive on average (Eq. 14), not hyperbolic.
  Ifs average("avg", ChannelLayout("xy"),
              {AffineMap(2, {1.5, 0, 0, 1.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {1, 0})}, {0.1, 0.9});
  EXPECT_EQ(average.classify(), Classification::AverageContractive);
  EXPECT_NEAR(average.average_log_contraction(), 0.1 * std::log(1.5) + 0.9 * std::log(0.5), 1e-12);
  // Every map expands: no attractor, and renderers refuse it.
  Ifs divergent("div", ChannelLayout("xy"),
                {AffineMap(2, {1.2, 0, 0, 1.2}, {0, 0}), AffineMap(2, {0, -1.1, 1.1, 0}, {1, 0})});
  EXPECT_EQ(divergent.classify(), Classification::Divergent);
  EXPECT_THROW(divergent.require_attractor(), DivergentSystemError);
}

TEST(Ifs, ValidatesInput) {
  const std::vector<AffineMap> two = {AffineMap(2), AffineMap(2)};
  EXPECT_THROW(Ifs("p", ChannelLayout("xy"), two, {0, 0}), InputError);
  EXPECT_THROW(Ifs("p", ChannelLayout("xy"), two, {1, -1}), InputError);
  EXPECT_THROW(Ifs("p", ChannelLayout("xy"), two, {1, NAN}), InputError);
  EXPECT_THROW(Ifs("p", ChannelLayout("xyz"), two), InputError);
  EXPECT_THROW(Ifs("p", ChannelLayout("xy"), {AffineMap(2, {NAN, 0, 0, 1}, {0, 0})}), InputError);
  EXPECT_THROW(Ifs("p", ChannelLayout("xy"), {}), InputError);
}

TEST(Ifs, JacobianProbabilitiesEq46) {
  const std::vector<AffineMap> maps = {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}),
                                       AffineMap(2, {0.25, 0, 0, 0.25}, {1, 0}),
                                       AffineMap(2, {0, 0, 0, 0.16}, {0, 0})};
  const auto p = jacobian_probabilities(maps, 2);
  // |det| = 0.25, 0.0625, 0 -> floored at 1% of 0.25.
  const double total = 0.25 + 0.0625 + 0.0025;
  EXPECT_NEAR(p[0], 0.25 / total, 1e-12);
  EXPECT_NEAR(p[1], 0.0625 / total, 1e-12);
  EXPECT_NEAR(p[2], 0.0025 / total, 1e-12);
}

TEST(Ifs, BoundsOfTheSierpinskiTriangle) {
  // The corners (0, 0), (1, 0), (0.5, 1) are fixed points: the bounds are exact.
  const Bounds b = plain_sierpinski().attractor_bounds();
  EXPECT_DOUBLE_EQ(b.lo[0], 0.0);
  EXPECT_DOUBLE_EQ(b.hi[0], 1.0);
  EXPECT_DOUBLE_EQ(b.lo[1], 0.0);
  EXPECT_DOUBLE_EQ(b.hi[1], 1.0);
}

// threads = 0 means the process default once one is set, and the hardware again after 0.
TEST(DefaultThreads, ZeroMeansTheProcessDefault) {
  const int hardware = resolve_threads(0);
  set_default_threads(3);
  EXPECT_EQ(resolve_threads(0), 3);
  EXPECT_EQ(resolve_threads(5), 5);
  set_default_threads(0);
  EXPECT_EQ(resolve_threads(0), hardware);
  EXPECT_THROW(set_default_threads(-1), InputError);
}
