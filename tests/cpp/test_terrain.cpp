// Fractal interpolation (Eq. 90-94) and IFS terrains (6.1.3.4): interpolation of the data,
// piecewise-linear / bilinear limits, self-affinity, the dimension theorem, exact control
// heights, mesh topology, determinism across thread counts, refusal of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"
#include "ifsforge/render/box_counting.h"
#include "ifsforge/interpolation/fractal_interpolation.h"
#include "ifsforge/interpolation/grid_recursion.h"
#include "ifsforge/interpolation/vertical_scaling.h"

using namespace ifsforge;

namespace {

// Unevenly spaced nodes whose spacings are powers of two of the range: the inverse maps are then
// exact in floating point, so point evaluation follows the true orbit of x. (For general nodes
// the orbit of a rounded x is only shadowed by a nearby exact one, and a rough graph is only
// Holder continuous: the tests would measure rounding, not the method.)
FractalInterpolation uneven(double a22) {
  return FractalInterpolation({-1.0, 1.0, 1.5, 2.0, 2.5, 3.0}, {0.5, 2.0, -1.0, 0.4, 1.1, 0.0},
                              {a22, -a22, 0.8 * a22, a22, -0.5 * a22});
}

double linear(const std::vector<double>& x, const std::vector<double>& f, double at) {
  std::size_t i = std::upper_bound(x.begin(), x.end(), at) - x.begin();
  i = std::clamp<std::size_t>(i, 1, x.size() - 1) - 1;
  return f[i] + (f[i + 1] - f[i]) * (at - x[i]) / (x[i + 1] - x[i]);
}

}  // namespace

TEST(FractalInterpolation, MapsSatisfyEq92) {
  const FractalInterpolation fif = uneven(0.6);
  const auto& x = fif.x();
  const auto& f = fif.values();
  for (std::size_t i = 0; i < fif.maps(); ++i) {
    const AffineMap w = fif.map(i);
    EXPECT_EQ(w.a(0, 1), 0.0);
    EXPECT_DOUBLE_EQ(w.a(1, 1), fif.vertical_scaling()[i]);
    Point first{}, last{};
    first[0] = x.front(), first[1] = f.front();
    last[0] = x.back(), last[1] = f.back();
    const Point a = w(first), b = w(last);
    EXPECT_NEAR(a[0], x[i], 1e-12);
    EXPECT_NEAR(a[1], f[i], 1e-12);
    EXPECT_NEAR(b[0], x[i + 1], 1e-12);
    EXPECT_NEAR(b[1], f[i + 1], 1e-12);
  }
}

TEST(FractalInterpolation, PassesThroughEveryDataPoint) {
  const FractalInterpolation fif = uneven(0.7);
  for (std::size_t i = 0; i < fif.x().size(); ++i) EXPECT_EQ(fif.evaluate(fif.x()[i]), fif.values()[i]);
  // Equally spaced nodes on a grid that contains them (4 intervals, 4 * 250 + 1 samples).
  const FractalInterpolation even({0, 1, 2, 3, 4}, {1.0, 3.0, -2.0, 0.5, 2.0}, {0.9, -0.7, 0.6, -0.95});
  const std::vector<double> s = even.sample(1001);
  for (int i = 0; i <= 4; ++i) EXPECT_NEAR(s[250 * i], even.values()[i], 1e-9);
}

TEST(FractalInterpolation, ZeroScalingIsPiecewiseLinear) {
  const FractalInterpolation fif = uneven(0.0);
  for (int k = 0; k <= 400; ++k) {
    const double at = -1.0 + 4.0 * k / 400.0;
    EXPECT_NEAR(fif.evaluate(at), linear(fif.x(), fif.values(), at), 1e-12) << at;
  }
  const FractalInterpolation even({0, 0.5, 1, 1.5}, {0, 2, 1, 5}, {0.0});
  const std::vector<double> s = even.sample(997);  // 996 is not a multiple of 3: nodes fall between samples
  for (std::size_t t = 0; t < s.size(); ++t)
    EXPECT_NEAR(s[t], linear(even.x(), even.values(), 1.5 * t / 996.0), 1e-12) << t;
  EXPECT_EQ(fif.dimension(), 1.0);
}

TEST(FractalInterpolation, GraphIsSelfAffine) {
  // The fixed-point equation of the attractor: f(L_i(x)) = a21_i x + a22_i f(x) + b2_i.
  const FractalInterpolation fif = uneven(0.75);
  Rng rng(3, 0);
  for (int k = 0; k < 200; ++k) {
    // x with 22 significant bits, so L_i(x) is exact too.
    const double x = -1.0 + 4.0 * double(rng.next() >> 42) / double(1 << 22);
    const double y = fif.evaluate(x);
    for (std::size_t i = 0; i < fif.maps(); ++i) {
      const AffineMap w = fif.map(i);
      const double mx = w.a(0, 0) * x + w.b(0), my = w.a(1, 0) * x + w.a(1, 1) * y + w.b(1);
      EXPECT_NEAR(fif.evaluate(mx), my, 1e-9) << "x=" << x << " map " << i;
    }
  }
}

TEST(FractalInterpolation, GridRecursionAgreesWithPointEvaluation) {
  // Two independent exact methods: the O(M) grid recursion and the unrolled series. Sample
  // counts whose M - 1 is coprime to N (every sample on a cycle), a multiple of N, and neither.
  // Rough factors at dyadic sample positions (exact orbits), gentle factors (|a22| N <= 1,
  // where rounding of x cannot be amplified) at any positions.
  const FractalInterpolation rough({0, 1, 2, 3, 4}, {0.0, 1.0, 0.2, 0.7, 0.3}, {0.8, -0.6, 0.7, -0.85});
  for (std::size_t m : {2u, 3u, 5u, 9u, 1025u, 4097u}) {
    const std::vector<double> s = rough.sample(m);
    for (std::size_t t = 0; t < m; t += 1 + m / 300)
      EXPECT_NEAR(s[t], rough.evaluate(4.0 * double(t) / double(m - 1)), 1e-9) << "M=" << m << " t=" << t;
  }
  const FractalInterpolation gentle({0, 1, 2, 3, 4}, {0.0, 1.0, 0.2, 0.7, 0.3}, {0.25, -0.2, 0.15, -0.25});
  for (std::size_t m : {8u, 1000u, 1024u, 3001u, 4096u}) {
    const std::vector<double> s = gentle.sample(m);
    for (std::size_t t = 0; t < m; t += 1 + m / 300)
      EXPECT_NEAR(s[t], gentle.evaluate(4.0 * double(t) / double(m - 1)), 1e-12) << "M=" << m << " t=" << t;
  }
}

TEST(FractalInterpolation, GridRecursionVisitsEverySampleOnce) {
  for (std::size_t n : {2u, 3u, 4u, 7u})
    for (std::size_t m : {2u, 9u, 100u, 1023u, 1024u}) {
      const GridRecursion plan(n, m);
      std::vector<int> seen(m, 0);
      for (const auto& op : plan.ops()) ++seen[op.target];
      EXPECT_EQ(plan.ops().size(), m);
      EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; })) << n << " " << m;
    }
}

TEST(FractalInterpolation, RandomIterationStaysOnTheGraph) {
  // Random iteration rounds x at every step; a gentle roughness keeps f Lipschitz, so the
  // rounding cannot be amplified and every point must lie on the graph to 1e-9.
  const FractalInterpolation fif = uneven(0.1);
  const Ifs ifs = fif.to_ifs();
  EXPECT_EQ(ifs.layout().text(), "xy");
  EXPECT_EQ(ifs.size(), 5u);
  std::size_t count = 0;
  sample_attractor(ifs, 20000, 7, [&](const Point& p) {
    EXPECT_NEAR(p[1], fif.evaluate(std::clamp(p[0], fif.x().front(), fif.x().back())), 1e-9);
    ++count;
  });
  EXPECT_EQ(count, 20000u);
}

TEST(FractalInterpolation, BoxDimensionFollowsTheVerticalScaling) {
  // Barnsley: for equally spaced, non-collinear data and sum |a22_i| > 1 the graph has
  // D = 1 + log(sum |a22_i|) / log N. Box counting for a graph: over columns of width delta,
  // N(delta) = sum ceil(oscillation / delta) boxes (Falconer 11.1), here from 4^11 + 1 exact
  // samples, for delta = 4^-2 .. 4^-6 (finer columns would hold too few samples to see their
  // oscillation); D is the least-squares slope of log N against log(1/delta).
  const int levels = 11;
  const std::size_t samples = (std::size_t(1) << (2 * levels)) + 1;
  double previous = 1.0;
  for (double d : {0.4, 0.55, 0.7, 0.85}) {
    const FractalInterpolation fif({0, 1, 2, 3, 4}, {0.0, 1.0, 0.35, 0.8, 0.1}, {d, -d, d, -d});
    const double theory = 1.0 + std::log(4.0 * d) / std::log(4.0);
    EXPECT_NEAR(fif.dimension(), theory, 1e-9);
    const std::vector<double> s = fif.sample(samples);
    const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const int first = 2, last = 6;
    for (int k = first; k <= last; ++k) {
      const std::size_t columns = std::size_t(1) << (2 * k), per = (samples - 1) / columns;
      const double delta = 1.0 / double(columns);
      double boxes = 0;
      for (std::size_t c = 0; c < columns; ++c) {
        const auto [a, b] = std::minmax_element(s.begin() + c * per, s.begin() + (c + 1) * per + 1);
        boxes += std::max(1.0, std::ceil((*b - *a) / (*hi - *lo) / delta));
      }
      const double x = std::log(1.0 / delta), y = std::log(boxes);
      sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const int n = last - first + 1;
    const double measured = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    EXPECT_NEAR(measured, theory, 0.05 * theory) << "a22 = " << d;
    EXPECT_GT(measured, previous + 0.05) << "the dimension grows with |a22|";
    previous = measured;
  }
}

TEST(FractalInterpolation, RefusesBadInput) {
  EXPECT_THROW(FractalInterpolation({0, 2, 1}, {0, 1, 2}, {0.1}), InputError);        // unsorted x
  EXPECT_THROW(FractalInterpolation({0, 1, 1}, {0, 1, 2}, {0.1}), InputError);        // repeated x
  EXPECT_THROW(FractalInterpolation({0, 1, 2}, {0, 1, 2}, {0.1, 1.0}), InputError);   // |a22| = 1
  EXPECT_THROW(FractalInterpolation({0, 1, 2}, {0, 1, 2}, {-1.5}), InputError);       // |a22| > 1
  EXPECT_THROW(FractalInterpolation({0, 1}, {0, 1}, {0.1}), InputError);              // too few points
  EXPECT_THROW(FractalInterpolation({0, 1, 2}, {0, 1}, {0.1}), InputError);           // sizes differ
  EXPECT_THROW(FractalInterpolation({0, 1, 2}, {0, NAN, 2}, {0.1}), InputError);      // NaN
  EXPECT_THROW(FractalInterpolation({0, 1, 2, 3}, {0, 1, 2, 3}, {0.1, 0.2}), InputError);  // a22 count
  try {
    FractalInterpolation({0, 1, 0.5, 2}, {0, 1, 2, 3}, {0.1});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x[2]"), std::string::npos) << e.what();
  }
  const FractalInterpolation fif = uneven(0.5);
  EXPECT_THROW(fif.evaluate(3.5), InputError);
  EXPECT_THROW(fif.sample(1), InputError);
}

TEST(VerticalScaling, PatternsAndSeeds) {
  EXPECT_EQ(vertical_scaling(4, 0.3, SignPattern::Constant), (std::vector<double>{0.3, 0.3, 0.3, 0.3}));
  EXPECT_EQ(vertical_scaling(3, -0.3, SignPattern::Alternating), (std::vector<double>{0.3, -0.3, 0.3}));
  const auto a = vertical_scaling(64, 0.5, SignPattern::Random, 9);
  EXPECT_EQ(a, vertical_scaling(64, 0.5, SignPattern::Random, 9));
  EXPECT_NE(a, vertical_scaling(64, 0.5, SignPattern::Random, 10));
  const auto negatives = std::count(a.begin(), a.end(), -0.5);
  EXPECT_GT(negatives, 16);
  EXPECT_LT(negatives, 48);
  EXPECT_THROW(vertical_scaling(3, 1.0), InputError);
  EXPECT_THROW(parse_name<SignPattern>("sometimes"), InputError);
}

// ---------------------------------------------------------------------------------------------
// Terrains
// ---------------------------------------------------------------------------------------------

#include "ifsforge/terrain/height_image.h"
#include "ifsforge/terrain/terrain.h"
#include "ifsforge/terrain/terrain_controls.h"
#include "ifsforge/terrain/terrain_mesh.h"

namespace {

TerrainControls regular_controls(int rows, int columns, double roughness_u, double roughness_v, std::uint64_t seed = 1) {
  TerrainControls c;
  c.heights = random_heights(TerrainGrid::Regular, rows, columns, {0.5}, 0.5, seed);
  c.a22_u = vertical_scaling(columns - 1, roughness_u, SignPattern::Random, seed, 1);
  c.a22_v = vertical_scaling(rows - 1, roughness_v, SignPattern::Random, seed, 2);
  c.size_x = 2.0;
  c.size_y = 1.5;
  return c;
}

TerrainControls crater(int angles, double roughness) {
  TerrainControls c;
  c.grid = TerrainGrid::Circular;
  c.radii = {0.0, 0.3, 0.55, 0.75, 1.0};
  c.heights = random_heights(TerrainGrid::Circular, 5, angles, {-0.2, -0.1, 0.6, 0.3, 0.0}, 0.08, 4);
  c.a22_u = {roughness};
  c.a22_v = {roughness};
  return c;
}

double bilinear(const std::vector<std::vector<double>>& h, double row, double column) {
  const std::size_t r = std::min<std::size_t>(std::size_t(row), h.size() - 2);
  const std::size_t c = std::min<std::size_t>(std::size_t(column), h[0].size() - 2);
  const double fr = row - r, fc = column - c;
  return (1 - fr) * ((1 - fc) * h[r][c] + fc * h[r][c + 1]) + fr * ((1 - fc) * h[r + 1][c] + fc * h[r + 1][c + 1]);
}

/// Every directed edge of the triangles, counted: a closed surface has each once, with its reverse once.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed_edges(const TriangleMesh& m) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[{t[k], t[(k + 1) % 3]}];
  return edges;
}

}  // namespace

TEST(Terrain, HitsItsControlHeightsExactly) {
  const TerrainControls c = regular_controls(5, 7, 0.6, 0.5);
  const Terrain t = make_terrain(c, 6 * 40 + 1, 4 * 30 + 1);
  for (int r = 0; r < 5; ++r)
    for (int k = 0; k < 7; ++k) EXPECT_EQ(t.height(30 * r, 40 * k), float(c.heights[r][k])) << r << " " << k;

  TerrainControls irregular = c;
  irregular.grid = TerrainGrid::Irregular;
  random_shifts(irregular, 0.3, 5);
  const Terrain ti = make_terrain(irregular, 6 * 40 + 1, 4 * 30 + 1);
  for (int r = 0; r < 5; ++r)
    for (int k = 0; k < 7; ++k) {
      EXPECT_EQ(ti.height(30 * r, 40 * k), float(c.heights[r][k]));
      // The sample sits on the displaced control point.
      const std::size_t i = std::size_t(30 * r) * ti.columns + 40 * k;
      EXPECT_NEAR(ti.u[i], (k + irregular.shift_u[r][k]) / 6.0, 1e-6);
      EXPECT_NEAR(ti.v[i], (r + irregular.shift_v[r][k]) / 4.0, 1e-6);
    }

  const TerrainControls circle = crater(12, 0.5);
  const Terrain tc = make_terrain(circle, 12 * 30, 4 * 25 + 1);
  for (int r = 0; r < 5; ++r)
    for (int k = 0; k < 12; ++k) EXPECT_EQ(tc.height(25 * r, 30 * k), float(circle.heights[r][k])) << r << " " << k;
}

TEST(Terrain, ZeroRoughnessIsBilinear) {
  TerrainControls c = regular_controls(6, 5, 0.0, 0.0, 3);
  // Sample counts whose spacing does not divide the control spacing.
  const Terrain t = make_terrain(c, 101, 77);
  for (int r = 0; r < t.rows; ++r)
    for (int k = 0; k < t.columns; ++k)
      ASSERT_NEAR(t.height(r, k), bilinear(c.heights, 5.0 * r / 76.0, 4.0 * k / 100.0), 2e-6) << r << " " << k;
  // On a circle the lattice is periodic in the angle.
  TerrainControls circle = crater(8, 0.0);
  const Terrain tc = make_terrain(circle, 100, 41);
  auto periodic = circle.heights;
  for (auto& row : periodic) row.push_back(row.front());
  for (int r = 0; r < tc.rows; ++r)
    for (int k = 0; k < tc.columns; ++k)
      ASSERT_NEAR(tc.height(r, k), bilinear(periodic, 4.0 * r / 40.0, 8.0 * k / 100.0), 2e-6) << r << " " << k;
}

TEST(Terrain, EveryVerticalInterpolatesTheLeadingVectors) {
  // Step 2 then step 3 of 6.1.3.4, recomputed with the 1D interpolant (the series, not the grid
  // recursion) at dyadic positions: 4 control intervals, 2^6 + 1 samples per direction. (Both
  // passes are linear in their data, so on a regular grid the surface is the tensor product
  // sum H_rc phi_c(u) psi_r(v) of the two directions' fractal cardinal functions.)
  const TerrainControls c = regular_controls(5, 5, 0.7, 0.45, 8);
  const Terrain t = make_terrain(c, 65, 65);
  const std::vector<double> nodes = {0, 1, 2, 3, 4};
  std::vector<FractalInterpolation> leading;
  for (int r = 0; r < 5; ++r) leading.emplace_back(nodes, c.heights[r], c.a22_u);
  for (int k = 0; k < 65; k += 3) {
    std::vector<double> column;
    for (int r = 0; r < 5; ++r) column.push_back(leading[r].evaluate(k / 16.0));
    const FractalInterpolation vertical(nodes, column, c.a22_v);
    for (int r = 0; r < 65; ++r) ASSERT_NEAR(t.height(r, k), vertical.evaluate(r / 16.0), 1e-5) << r << " " << k;
  }
}

TEST(Terrain, RoughnessPerDirection) {
  // Rough along the leading vectors only: every vertical is piecewise linear between them.
  const TerrainControls c = regular_controls(5, 5, 0.75, 0.0, 2);
  const Terrain t = make_terrain(c, 257, 257);
  double across = 0, along = 0;
  for (int r = 1; r + 1 < t.rows; ++r)
    for (int k = 1; k + 1 < t.columns; ++k) {
      if (r % 64 != 0) across = std::max(across, double(std::fabs(t.height(r + 1, k) - 2 * t.height(r, k) + t.height(r - 1, k))));
      if (k % 64 != 0) along = std::max(along, double(std::fabs(t.height(r, k + 1) - 2 * t.height(r, k) + t.height(r, k - 1))));
    }
  EXPECT_LT(across, 1e-5);
  EXPECT_GT(along, 1e-2);
}

TEST(Terrain, SameBytesForAnyThreadCount) {
  TerrainControls c = regular_controls(9, 9, 0.55, 0.5, 6);
  c.grid = TerrainGrid::Irregular;
  random_shifts(c, 0.35, 2);
  const Terrain one = make_terrain(c, 1000, 700, 1), two = make_terrain(c, 1000, 700, 2);
  EXPECT_EQ(one.heights, two.heights);
  EXPECT_EQ(one.u, two.u);
  EXPECT_EQ(one.v, two.v);
  EXPECT_EQ(height_image(one, 640, 480, 1).pixels, height_image(two, 640, 480, 2).pixels);
  const TriangleMesh m1 = terrain_mesh(one, {}, 1), m2 = terrain_mesh(two, {}, 2);
  EXPECT_EQ(m1.positions, m2.positions);
  EXPECT_EQ(m1.normals, m2.normals);
  EXPECT_EQ(m1.triangles, m2.triangles);
  const Terrain c1 = make_terrain(crater(16, 0.5), 512, 128, 1), c2 = make_terrain(crater(16, 0.5), 512, 128, 2);
  EXPECT_EQ(c1.heights, c2.heights);
  EXPECT_EQ(height_image(c1, 255, 255, 1).pixels, height_image(c2, 255, 255, 2).pixels);
}

TEST(Terrain, HeightImageOfTheSurface) {
  // The rasteriser, at pixels that fall on the samples of an undisplaced irregular grid, must
  // give the regular grid's image (north up: image row 0 is the last sample row).
  const TerrainControls c = regular_controls(5, 6, 0.5, 0.4, 9);
  const Terrain regular = make_terrain(c, 81, 61);
  TerrainControls flat = c;
  flat.grid = TerrainGrid::Irregular;
  const Terrain irregular = make_terrain(flat, 81, 61);
  const Image a = height_image(regular), b = height_image(irregular, 81, 61);
  ASSERT_EQ(a.width, 81);
  ASSERT_EQ(a.height, 61);
  for (std::size_t i = 0; i < a.pixels.size(); ++i) ASSERT_NEAR(a.pixels[i], b.pixels[i], 1e-5) << i;
  EXPECT_NEAR(a.at(0, 60, 0), (c.heights[0][0] - regular.min_height) / (regular.max_height - regular.min_height), 1e-6);
  EXPECT_NEAR(a.at(80, 0, 0), (c.heights[4][5] - regular.min_height) / (regular.max_height - regular.min_height), 1e-6);
  // A crater: the centre pixel is the centre height; corners outside the circle take the rim.
  const TerrainControls ring = crater(12, 0.4);
  const Terrain tc = make_terrain(ring, 360, 101);
  const Image ci = height_image(tc, 201, 201);
  const double range = tc.max_height - tc.min_height;
  EXPECT_NEAR(ci.at(100, 100, 0), (ring.heights[0][0] - tc.min_height) / range, 1e-5);
  // East (angle 0) on the rim at the image's right edge centre, north (90°) at the top centre.
  EXPECT_NEAR(ci.at(200, 100, 0), (ring.heights[4][0] - tc.min_height) / range, 1e-4);
  EXPECT_NEAR(ci.at(100, 0, 0), (ring.heights[4][3] - tc.min_height) / range, 1e-4);
  for (float p : ci.pixels) ASSERT_TRUE(p >= 0.0f && p <= 1.0f);
}

TEST(Terrain, MeshTopology) {
  const TerrainControls c = regular_controls(5, 5, 0.5, 0.5, 4);
  const Terrain t = make_terrain(c, 33, 17);
  const TriangleMesh open = terrain_mesh(t);
  EXPECT_EQ(open.positions.size(), 33u * 17u);
  EXPECT_EQ(open.triangles.size(), 2u * 32u * 16u);
  EXPECT_EQ(open.uvs.size(), open.positions.size());
  // An open sheet: interior edges twice (once each way), the outline's edges once.
  int boundary = 0;
  const auto edges = directed_edges(open);
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1);
    if (!edges.count({e.second, e.first})) ++boundary;
  }
  EXPECT_EQ(boundary, 2 * 32 + 2 * 16);
  for (const auto& n : open.normals) EXPECT_GT(n[2], 0.0f);  // our axes, z up: every normal points up

  TerrainMeshOptions solid;
  solid.solid = true;
  const TriangleMesh closed = terrain_mesh(t, solid);
  EXPECT_EQ(closed.positions.size(), 33u * 17u + (2 * 32 + 2 * 16) + 1);
  // Watertight: every directed edge once, and its reverse once.
  const auto closed_edges = directed_edges(closed);
  for (const auto& [e, n] : closed_edges) ASSERT_TRUE(n == 1 && closed_edges.count({e.second, e.first}));
  // Euler characteristic of a closed sphere-like surface: V - E + F = 2.
  EXPECT_EQ(long(closed.positions.size()) - long(closed_edges.size() / 2) + long(closed.triangles.size()), 2);
  // Outward orientation: the signed volume is positive.
  double volume = 0;
  for (const auto& tri : closed.triangles) {
    const auto& a = closed.positions[tri[0]];
    const auto& b = closed.positions[tri[1]];
    const auto& d = closed.positions[tri[2]];
    volume += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) + a[2] * (b[0] * d[1] - b[1] * d[0])) / 6.0;
  }
  EXPECT_GT(volume, 0.0);

  // A crater: one centre vertex, no seam: only the outer circle is boundary.
  const Terrain tc = make_terrain(crater(10, 0.5), 80, 21);
  const TriangleMesh disk = terrain_mesh(tc);
  EXPECT_EQ(disk.positions.size(), 1u + 80u * 20u);
  EXPECT_EQ(disk.triangles.size(), 80u + 2u * 80u * 19u);
  int rim = 0;
  const auto disk_edges = directed_edges(disk);
  for (const auto& [e, n] : disk_edges) {
    EXPECT_EQ(n, 1);
    if (!disk_edges.count({e.second, e.first})) ++rim;
  }
  EXPECT_EQ(rim, 80);
  EXPECT_EQ(long(disk.positions.size()) - long((disk_edges.size() + rim) / 2) + long(disk.triangles.size()), 1);
  TerrainMeshOptions closed_disk;
  closed_disk.solid = true;
  const TriangleMesh volcano = terrain_mesh(tc, closed_disk);
  const auto ve = directed_edges(volcano);
  for (const auto& [e, n] : ve) ASSERT_TRUE(n == 1 && ve.count({e.second, e.first}));
}

TEST(Terrain, ControlsFromAHeightMap) {
  // A map whose value is its normalised x (vertex-centred): controls sampled over a window
  // take the window's x at their positions.
  Image map(101, 51, 1);
  for (int y = 0; y < 51; ++y)
    for (int x = 0; x < 101; ++x) map.at(x, y, 0) = x / 100.0f;
  TerrainControls c;
  sample_heights(c, 5, 6, map, {0.2, 0.0, 0.7, 1.0}, 10.0, 20.0);
  for (int r = 0; r < 5; ++r)
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(c.heights[r][k], 10.0 + 10.0 * (0.2 + 0.5 * k / 5.0), 1e-4);
  // North up: a map whose value is 1 - y / (height - 1) puts 1 on the last control row.
  for (int y = 0; y < 51; ++y)
    for (int x = 0; x < 101; ++x) map.at(x, y, 0) = 1.0f - y / 50.0f;
  sample_heights(c, 5, 6, map, {0, 0, 1, 1});
  EXPECT_NEAR(c.heights[4][2], 1.0, 1e-5);
  EXPECT_NEAR(c.heights[0][2], 0.0, 1e-5);
  EXPECT_THROW(sample_heights(c, 5, 6, map, {0.5, 0, 0.4, 1}), InputError);
  EXPECT_EQ(random_heights(TerrainGrid::Regular, 5, 5, {0}, 1, 3), random_heights(TerrainGrid::Regular, 5, 5, {0}, 1, 3));
  EXPECT_NE(random_heights(TerrainGrid::Regular, 5, 5, {0}, 1, 3), random_heights(TerrainGrid::Regular, 5, 5, {0}, 1, 4));
}

TEST(Terrain, RefusesBadInput) {
  TerrainControls c = regular_controls(5, 5, 0.3, 0.3);
  auto refuses = [](const TerrainControls& bad, const std::string& words) {
    try {
      make_terrain(bad, 65, 65);
      ADD_FAILURE() << "accepted; expected an error about " << words;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  TerrainControls small = regular_controls(4, 5, 0.3, 0.3);
  refuses(small, "at least 5 x 5");
  TerrainControls steep = c;
  steep.a22_u = {0.3, 1.0, 0.2, 0.1};
  refuses(steep, "|a22| < 1");
  TerrainControls count = c;
  count.a22_v = {0.1, 0.2};
  refuses(count, "a22_v needs 4");
  TerrainControls shifted = c;
  shifted.shift_u.assign(5, std::vector<double>(5, 0.1));
  refuses(shifted, "irregular grid");
  shifted.grid = TerrainGrid::Irregular;
  refuses(shifted, "outline");
  TerrainControls nan = c;
  nan.heights[2][3] = NAN;
  refuses(nan, "heights [2][3]");
  TerrainControls folded = c;
  folded.grid = TerrainGrid::Irregular;
  folded.shift_u.assign(5, {0.0, 0.45, -0.45, 0.45, 0.0});
  folded.a22_shift = {0.95};
  refuses(folded, "folds");
  TerrainControls ring = crater(8, 0.3);
  ring.radii[0] = 0.1;
  refuses(ring, "radii[0]");
  ring = crater(8, 0.3);
  ring.heights[0][3] += 1.0;
  refuses(ring, "centre");
  ring = crater(8, 0.3);
  ring.radii[2] = ring.radii[1];
  refuses(ring, "increase");
}
