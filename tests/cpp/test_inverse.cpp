// The inverse problem: distance transforms, collage distance (Eq. 41-42), fitting.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/image.h"
#include "ifsforge/core/random.h"
#include "ifsforge/inverse/cma_es.h"
#include "ifsforge/inverse/collage.h"
#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/inverse/fit.h"

namespace ifsforge {
namespace {

PixelSet random_set(int w, int h, double density, std::uint64_t seed) {
  Rng rng(seed, 0);
  PixelSet s{w, h, std::vector<std::uint8_t>(std::size_t(w) * h)};
  for (auto& c : s.cells) c = rng.uniform() < density;
  return s;
}

/// Eq. 12 by brute force over every pair of pixels.
double brute_hausdorff(const PixelSet& a, const PixelSet& b) {
  auto directed = [](const PixelSet& from, const PixelSet& to) {
    double worst = 0;
    for (int y = 0; y < from.height; ++y)
      for (int x = 0; x < from.width; ++x) {
        if (!from.cells[std::size_t(y) * from.width + x]) continue;
        double best = std::numeric_limits<double>::infinity();
        for (int v = 0; v < to.height; ++v)
          for (int u = 0; u < to.width; ++u)
            if (to.cells[std::size_t(v) * to.width + u]) best = std::min(best, std::hypot(x - u, y - v));
        worst = std::max(worst, best);
      }
    return worst;
  };
  return std::max(directed(a, b), directed(b, a));
}

TEST(Inverse, DistanceTransformIsExact) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const PixelSet s = random_set(17 + int(seed % 5), 13 + int(seed % 3), 0.02 + 0.01 * (seed % 4), seed);
    const auto dt = squared_distance_transform(s);
    for (int y = 0; y < s.height; ++y)
      for (int x = 0; x < s.width; ++x) {
        double best = std::numeric_limits<double>::infinity();
        for (int v = 0; v < s.height; ++v)
          for (int u = 0; u < s.width; ++u)
            if (s.cells[std::size_t(v) * s.width + u]) best = std::min(best, double((x - u) * (x - u) + (y - v) * (y - v)));
        ASSERT_EQ(dt[std::size_t(y) * s.width + x], best) << "seed " << seed << " at " << x << "," << y;
      }
  }
}

TEST(Inverse, HausdorffEqualsBruteForce) {
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    const PixelSet a = random_set(24, 19, 0.05, seed), b = random_set(24, 19, 0.03, seed + 100);
    EXPECT_DOUBLE_EQ(hausdorff_distance(a, b), brute_hausdorff(a, b)) << "seed " << seed;
  }
}

TEST(Inverse, CollageDistanceEqualsBruteForceHausdorff) {
  // Two maps sending the unit square to halves of itself, a blob target on [0, 1]^2.
  const Ifs ifs("halves", ChannelLayout("xy"),
                {AffineMap(2, {0.5, 0, 0, 0.7}, {0, 0.1}), AffineMap(2, {0.4, 0.1, -0.1, 0.5}, {0.55, 0.3})});
  const PixelSet target = random_set(20, 20, 0.15, 7);
  const Window window{0, 0, 1, 1};
  const CollageReport r = collage_distance(ifs, target, window);
  // The collage by hand: every 2 x 2 sub-sample of a target pixel, mapped, marks its pixel.
  const int pad = 10;
  PixelSet padded = pad_pixels(target, pad), collage{40, 40, std::vector<std::uint8_t>(1600)};
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
      if (target.cells[y * 20 + x])
        for (const AffineMap& m : ifs.maps())
          for (double sy : {0.25, 0.75})
            for (double sx : {0.25, 0.75}) {
              const Point p{(x + sx) / 20.0, 1.0 - (y + sy) / 20.0};
              const Point q = m(p);
              const int ix = int(std::floor(q[0] * 20)) + pad, iy = int(std::floor((1.0 - q[1]) * 20)) + pad;
              collage.cells[std::size_t(std::clamp(iy, 0, 39)) * 40 + std::clamp(ix, 0, 39)] = 1;
            }
  EXPECT_DOUBLE_EQ(r.distance_pixels, brute_hausdorff(padded, collage));
  EXPECT_DOUBLE_EQ(r.distance, r.distance_pixels / 20.0);
  const double s = std::max(ifs.map(0).contraction_factor(2), ifs.map(1).contraction_factor(2));
  EXPECT_DOUBLE_EQ(r.contraction, s);
  EXPECT_DOUBLE_EQ(r.bound, r.distance / (1 - s));
}

TEST(Inverse, CollageOfASelfSimilarSquareIsZero) {
  // The filled square is exactly the union of its four half copies.
  std::vector<AffineMap> maps;
  for (double ty : {0.0, 0.5})
    for (double tx : {0.0, 0.5}) maps.push_back(AffineMap(2, {0.5, 0, 0, 0.5}, {tx, ty}));
  const Ifs ifs("square", ChannelLayout("xy"), maps);
  PixelSet full{32, 32, std::vector<std::uint8_t>(1024, 1)};
  const CollageReport r = collage_distance(ifs, full, Window{0, 0, 1, 1});
  EXPECT_EQ(r.distance_pixels, 0.0);
  EXPECT_EQ(r.collage_pixels, 1024u);
  EXPECT_EQ(r.bound, 0.0);
}

// Which side is the shape: a white right triangle on black touching the bottom and left edges
// (half the border) is the shape; a black disc on white touching the frame in a few pixels too.
TEST(Inverse, ForegroundOfAShapeTouchingTheFrame) {
  Image triangle(32, 32, 1);
  std::size_t inside = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x)
      if (x <= y) triangle.at(x, y, 0) = 1.0f, ++inside;  // row 31 is the bottom edge
  const PixelSet t = foreground(triangle);
  EXPECT_EQ(t.count(), inside);
  EXPECT_TRUE(t.cells[31 * 32]);
  Image disc(32, 32, 1);
  std::size_t dark = 0;
  for (int y = 0; y < 32; ++y)
    for (int x = 0; x < 32; ++x) {
      const bool in = std::hypot(x - 15.5, y - 2.0) < 6;  // cut by the top edge
      disc.at(x, y, 0) = in ? 0.0f : 1.0f;
      dark += in;
    }
  const PixelSet d = foreground(disc);
  EXPECT_EQ(d.count(), dark);
  EXPECT_TRUE(d.cells[15]);
  // Bright throughout: a filled frame; dark throughout: no shape.
  Image bright(8, 8, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) bright.at(x, y, 0) = 1.0f;
  EXPECT_EQ(foreground(bright).count(), 64u);
  EXPECT_THROW(foreground(Image(8, 8, 1)), InputError);
}

// A value at the floor is never replaced (only a smaller one is), so stopping there ends with
// the result the full search ends with, in fewer evaluations; a start at the floor costs one.
TEST(Inverse, CmaStopsAtItsFloorWithTheSameResult) {
  auto f = [](const std::vector<double>& x, int) {
    return std::max(0.0, (x[0] - 3) * (x[0] - 3) + (x[1] + 1) * (x[1] + 1) - 0.25);
  };
  CmaOptions o;
  o.seed = 5;
  o.max_generations = 300;
  o.tolerance = 0;
  const CmaResult full = minimize_cma(f, {0, 0}, {1, 1}, o);
  o.floor = 0;
  const CmaResult floored = minimize_cma(f, {0, 0}, {1, 1}, o);
  ASSERT_EQ(full.value, 0.0);
  EXPECT_EQ(floored.value, 0.0);
  EXPECT_EQ(floored.best, full.best);
  EXPECT_LT(floored.evaluations, full.evaluations / 4);
  EXPECT_EQ(minimize_cma(f, {3, -1}, {1, 1}, o).evaluations, 1u);
}

// A caller's goal ends the search at the first best that meets it: the fits stop when a best's
// corners, snapped onto the lattice, draw the target exactly.
TEST(Inverse, CmaStopsAtTheFirstBestThatReachesItsGoal) {
  auto f = [](const std::vector<double>& x, int) { return (x[0] - 3) * (x[0] - 3) + (x[1] + 1) * (x[1] + 1); };
  CmaOptions o;
  o.seed = 5;
  o.max_generations = 300;
  o.tolerance = 0;
  const CmaResult full = minimize_cma(f, {0, 0}, {1, 1}, o);
  int asked = 0;
  o.reached = [&](const std::vector<double>& x) { return ++asked, f(x, 0) < 0.01; };
  const CmaResult goal = minimize_cma(f, {0, 0}, {1, 1}, o);
  EXPECT_LT(goal.value, 0.01);
  EXPECT_GT(goal.value, full.value);
  EXPECT_LT(goal.evaluations, full.evaluations / 4);
  EXPECT_LT(asked, int(goal.evaluations));  // asked of new bests only
}

// A negative overlap weight would reward overlapping copies and let a fit's value fall below the
// floor its searches stop at.
TEST(Inverse, FitRefusesANegativeOverlapWeight) {
  PixelSet square{16, 16, std::vector<std::uint8_t>(256, 1)};
  FitOptions o;
  o.overlap_weight = -1;
  EXPECT_THROW(fit_ifs(square, o), InputError);
  o.overlap_weight = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fit_ifs(square, o), InputError);
}

}  // namespace
}  // namespace ifsforge
