// The structural candidates of the planar fit's cover start (cpp/src/inverse/fit_moments.h):
// a similarity's image of a point set is matched by one of the moment maps exactly, at any turn.
#include <gtest/gtest.h>

#include <cmath>

#include "../../cpp/src/inverse/fit_moments.h"
#include "../../cpp/src/inverse/fit_shared.h"
#include "ifsforge/core/random.h"

namespace ifsforge {
namespace {

TEST(FitMoments, SomeMomentMapIsTheSimilarityThatMadeThePiece) {
  // An elongated, lopsided cloud: its covariance has a clear principal axis.
  Rng rng(3, 0);
  std::vector<std::array<double, 2>> whole;
  for (int i = 0; i < 400; ++i) {
    const double u = rng.uniform(), v = rng.uniform();
    whole.push_back({0.2 + 0.6 * u * u, 0.1 + 0.2 * v + 0.1 * u});
  }
  for (double turn : {0.3, 2.5, -2.9, 4.0})  // radians: turns beyond any half circle too
    for (double sign : {1.0, -1.0}) {      // unmirrored and mirrored
      const double p[6] = {sign * 0.4, 0.4, turn, turn, 0.3, -0.2};
      AffineMap w;
      decode_map(p, 2, 0.9, w);
      std::vector<std::array<double, 2>> piece;
      for (const auto& q : whole)
        piece.push_back({w.a(0, 0) * q[0] + w.a(0, 1) * q[1] + w.b(0), w.a(1, 0) * q[0] + w.a(1, 1) * q[1] + w.b(1)});
      double nearest = 1e9;
      for (const auto& c : moment_maps(moments_of(whole), moments_of(piece), 0.9, 0)) {
        AffineMap m;
        decode_map(c.data(), 2, 0.9, m);
        double d = std::abs(m.b(0) - w.b(0)) + std::abs(m.b(1) - w.b(1));
        for (int r = 0; r < 2; ++r)
          for (int k = 0; k < 2; ++k) d += std::abs(m.a(r, k) - w.a(r, k));
        nearest = std::min(nearest, d);
      }
      EXPECT_LT(nearest, 1e-9) << "turn " << turn << " sign " << sign;
    }
}

TEST(FitMoments, EllipseMapCarriesTheWholesMomentsOntoThePieces) {
  // A lopsided cloud and a thin, turned piece: w(whole) has the piece's centroid and covariance
  // (A cov_W A^T = cov_P) at any turn Q and with or without the mirror.
  Rng rng(5, 0);
  std::vector<std::array<double, 2>> whole, piece;
  for (int i = 0; i < 300; ++i) {
    const double u = rng.uniform(), v = rng.uniform();
    whole.push_back({0.2 + 0.6 * u * u, 0.1 + 0.5 * v + 0.1 * u});
    piece.push_back({0.5 + 0.3 * u + 0.02 * v, 0.4 + 0.2 * u - 0.03 * v});
  }
  const Moments mw = moments_of(whole), mp = moments_of(piece);
  for (double turn : {0.0, 1.1, -2.7})
    for (bool mirror : {false, true}) {
      const auto p = ellipse_map(mw, mp, turn, mirror);
      AffineMap w;
      decode_map(p.data(), 2, 0.99, w);
      std::vector<std::array<double, 2>> image;
      for (const auto& q : whole)
        image.push_back({w.a(0, 0) * q[0] + w.a(0, 1) * q[1] + w.b(0), w.a(1, 0) * q[0] + w.a(1, 1) * q[1] + w.b(1)});
      const Moments mi = moments_of(image);
      EXPECT_NEAR(mi.centroid[0], mp.centroid[0], 1e-12);
      EXPECT_NEAR(mi.centroid[1], mp.centroid[1], 1e-12);
      EXPECT_NEAR(mi.xx, mp.xx, 1e-12);
      EXPECT_NEAR(mi.xy, mp.xy, 1e-12);
      EXPECT_NEAR(mi.yy, mp.yy, 1e-12);
      EXPECT_EQ(w.a(0, 0) * w.a(1, 1) - w.a(0, 1) * w.a(1, 0) < 0, mirror) << "turn " << turn;
    }
}

TEST(FitMoments, MomentMapsTryTheFullCircle) {
  Moments round;
  round.xx = round.yy = 1;
  const auto maps = moment_maps(round, round, 0.9, 36);
  ASSERT_EQ(maps.size(), 2u * (4 + 36));
  EXPECT_DOUBLE_EQ(maps[4 + 18][2], M_PI);  // the 18th of 36 turns: half the circle
}

TEST(FitMoments, MaskPartsAreTheSeparatedBlocksLargestFirst) {
  const int w = 10, h = 6;
  std::vector<std::uint8_t> grown(w * h, 0), on(w * h, 0);
  auto fill = [&](int x0, int y0, int x1, int y1) {
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) grown[y * w + x] = 1, on[y * w + x] = (x + y) % 2;
  };
  fill(0, 0, 2, 2);   // 4 cells, 2 of them on
  fill(4, 1, 10, 5);  // 24 cells, 12 on
  const auto parts = mask_parts(grown, on, w, h, 8);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].size(), 12u);
  EXPECT_EQ(parts[1].size(), 2u);
  EXPECT_EQ(mask_parts(grown, on, w, h, 1).size(), 1u);
  fill(2, 0, 4, 2);  // a bridge: one part, no pieces
  EXPECT_TRUE(mask_parts(grown, on, w, h, 8).empty());
}

TEST(FitMoments, SymmetricCopiesAreTheCopiesReflectedAndTurnedAboutTheCentroid) {
  // A cloud symmetric in the vertical line and the horizontal one through (0.5, 0.4).
  std::vector<std::array<double, 2>> whole;
  for (int i = 0; i < 50; ++i)
    for (double sx : {-1.0, 1.0})
      for (double sy : {-1.0, 1.0}) whole.push_back({0.5 + sx * 0.01 * i, 0.4 + sy * 0.003 * i * (i % 7)});
  const Moments m = moments_of(whole);
  for (double sign : {1.0, -1.0}) {
    const std::vector<double> x0 = {sign * 0.4, 0.4, 0.8, 0.8, 0.1, 0.3};
    AffineMap w;
    decode_map(x0.data(), 2, 0.9, w);
    // What each symmetry S makes of the copy: S(w(x)), with S about the centroid.
    const double mirror_x[2][2] = {{-1, 0}, {0, 1}}, mirror_y[2][2] = {{1, 0}, {0, -1}}, half[2][2] = {{-1, 0}, {0, -1}};
    for (const auto* S : {mirror_x, mirror_y, half}) {
      AffineMap want(2);
      for (int r = 0; r < 2; ++r) {
        want.b(r) = m.centroid[r];
        for (int k = 0; k < 2; ++k) {
          want.a(r, k) = S[r][0] * w.a(0, k) + S[r][1] * w.a(1, k);
          want.b(r) += S[r][k] * (w.b(k) - m.centroid[k]);
        }
      }
      double nearest = 1e9;
      for (const auto& p : symmetric_copies(x0, m)) {
        AffineMap got;
        decode_map(p.data(), 2, 0.9, got);
        double d = 0;
        for (int r = 0; r < 2; ++r) {
          d += std::abs(got.b(r) - want.b(r));
          for (int k = 0; k < 2; ++k) d += std::abs(got.a(r, k) - want.a(r, k));
        }
        nearest = std::min(nearest, d);
      }
      EXPECT_LT(nearest, 1e-9) << "sign " << sign;
    }
  }
}

}  // namespace
}  // namespace ifsforge
