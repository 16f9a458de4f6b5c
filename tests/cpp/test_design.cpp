// Interactive design: preview clouds (the collage of chapter 4) and morphing.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "ifsforge/core/error.h"
#include "ifsforge/design/morph.h"
#include "ifsforge/design/preview.h"
#include "ifsforge/model/map_params.h"

using namespace ifsforge;

namespace {

Ifs weighted_sierpinski(std::vector<double> p = {1, 1, 1}) {
  std::vector<AffineMap> maps;
  for (auto [x, y] : {std::pair{0.0, 0.0}, {0.5, 0.0}, {0.25, 0.5}})
    maps.emplace_back(2, std::vector<double>{0.5, 0, 0, 0.5}, std::vector<double>{x, y});
  return Ifs("sierpinski", ChannelLayout("xy"), maps, p);
}

/// xy+rgb: map i halves the position towards its corner and sets the colour to colours[i].
Ifs coloured(const std::vector<std::array<double, 3>>& colours) {
  std::vector<AffineMap> maps;
  const double corners[3][2] = {{0, 0}, {0.5, 0}, {0.25, 0.5}};
  for (std::size_t i = 0; i < colours.size(); ++i) {
    AffineMap m(5);
    for (int r = 0; r < 5; ++r) m.a(r, r) = r < 2 ? 0.5 : 0.0;
    m.b(0) = corners[i][0];
    m.b(1) = corners[i][1];
    for (int c = 0; c < 3; ++c) m.b(2 + c) = colours[i][c];
    maps.push_back(m);
  }
  return Ifs("coloured", ChannelLayout("xy+rgb"), maps, std::vector<double>(colours.size(), 1.0));
}

AffineMap from_params(double scale, double angle, bool reflect_y, double tx) {
  MapParams p;
  p.scale = {scale, scale, 1};
  p.rotation = {angle, angle, 0};
  p.reflect = {false, reflect_y, false};
  p.translation = {tx, 0, 0};
  return map_from_params(p);
}

double max_difference(const AffineMap& a, const AffineMap& b) {
  double d = 0.0;
  for (int r = 0; r < a.dim(); ++r) {
    d = std::max(d, std::abs(a.b(r) - b.b(r)));
    for (int c = 0; c < a.dim(); ++c) d = std::max(d, std::abs(a.a(r, c) - b.a(r, c)));
  }
  return d;
}

}  // namespace

TEST(PreviewCloud, EveryPointLiesInThePieceOfItsLastMap) {
  // The collage A = w_0(A) u w_1(A) u w_2(A): the Sierpinski pieces are the three half-size
  // triangles, inside the boxes [0, .5]x[0, .5], [.5, 1]x[0, .5], [.25, .75]x[.5, 1].
  PreviewOptions o;
  o.count = 150000;
  const PreviewCloud cloud = preview_cloud(weighted_sierpinski(), o);
  ASSERT_EQ(cloud.positions.size(), o.count * 3);
  const double lo[3][2] = {{0, 0}, {0.5, 0}, {0.25, 0.5}};
  for (std::size_t k = 0; k < cloud.count; ++k) {
    const auto i = cloud.pieces[k];
    ASSERT_LT(i, 3u);
    const float x = cloud.positions[k * 3], y = cloud.positions[k * 3 + 1];
    ASSERT_GE(x, lo[i][0] - 1e-6);
    ASSERT_LE(x, lo[i][0] + 0.5 + 1e-6);
    ASSERT_GE(y, lo[i][1] - 1e-6);
    ASSERT_LE(y, lo[i][1] + 0.5 + 1e-6);
    ASSERT_EQ(cloud.positions[k * 3 + 2], 0.0f);  // planar systems lie in z = 0
  }
  // Hyperbolic: bounds are the extremes of the cloud. The corners are fixed points; a run of
  // k equal maps comes within 2^-k of one, and 150k points hold runs of about log_3(150k) = 11.
  EXPECT_NEAR(cloud.bounds.lo[0], 0.0, 2e-3);
  EXPECT_NEAR(cloud.bounds.hi[0], 1.0, 2e-3);
  EXPECT_NEAR(cloud.bounds.hi[1], 1.0, 2e-3);
  EXPECT_GE(cloud.bounds.lo[1], 0.0);
}

TEST(PreviewCloud, PieceFrequenciesFollowTheProbabilities) {
  PreviewOptions o;
  o.count = 200000;
  const std::vector<double> p = {0.6, 0.3, 0.1};
  const PreviewCloud cloud = preview_cloud(weighted_sierpinski(p), o);
  std::vector<double> hits(3, 0.0);
  for (auto i : cloud.pieces) hits[i] += 1;
  for (int i = 0; i < 3; ++i) {
    const double sigma = std::sqrt(p[i] * (1 - p[i]) / o.count);
    EXPECT_NEAR(hits[i] / o.count, p[i], 5 * sigma) << "map " << i;
  }
}

TEST(PreviewCloud, SameCloudForAnyThreadCount) {
  PreviewOptions o;
  o.count = 300000;  // several jobs
  o.seed = 7;
  o.threads = 1;
  const PreviewCloud one = preview_cloud(coloured({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}), o);
  o.threads = 2;
  const PreviewCloud two = preview_cloud(coloured({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}), o);
  EXPECT_EQ(one.positions, two.positions);
  EXPECT_EQ(one.colors, two.colors);
  EXPECT_EQ(one.pieces, two.pieces);
  EXPECT_EQ(one.bounds.lo, two.bounds.lo);
  o.seed = 8;
  EXPECT_NE(preview_cloud(coloured({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}), o).positions, one.positions);
}

TEST(PreviewCloud, ChannelColorsAreTheLayoutsColors) {
  PreviewOptions o;
  o.count = 20000;
  // Colours in [0, 1] are shown as they are: piece i carries colour i exactly.
  const PreviewCloud unit = preview_cloud(coloured({{1, 0, 0}, {0, 1, 0}, {0.2, 0.4, 0.6}}), o);
  EXPECT_EQ(unit.coloring, PreviewColoring::Channels);  // auto: the layout has colour
  const float expected[3][3] = {{1, 0, 0}, {0, 1, 0}, {0.2f, 0.4f, 0.6f}};
  for (std::size_t k = 0; k < unit.count; ++k)
    for (int c = 0; c < 3; ++c) ASSERT_FLOAT_EQ(unit.colors[k * 4 + c], expected[unit.pieces[k]][c]);
  // Outside [0, 1], Eq. 101 maps each channel's range onto [0, 1]: red 2 -> 1, -1 -> 0, 0.5 -> 0.5.
  const PreviewCloud wide = preview_cloud(coloured({{2, 0, 0}, {-1, 0, 0}, {0.5, 0, 0}}), o);
  const float red[3] = {1.0f, 0.0f, 0.5f};
  for (std::size_t k = 0; k < wide.count; ++k) ASSERT_NEAR(wide.colors[k * 4], red[wide.pieces[k]], 1e-6);
  for (std::size_t k = 0; k < wide.count; ++k) ASSERT_EQ(wide.colors[k * 4 + 3], 1.0f);
}

TEST(PreviewCloud, PieceColorsAndHighlight) {
  PreviewOptions o;
  o.count = 5000;
  o.coloring = PreviewColoring::Pieces;
  o.highlight = 1;
  const PreviewCloud cloud = preview_cloud(coloured({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}), o);
  float bright[4], dim[4];
  for (std::size_t k = 0; k < cloud.count; ++k) {
    piece_color(cloud.pieces[k], false, bright);
    piece_color(cloud.pieces[k], true, dim);
    const float* expect = cloud.pieces[k] == 1 ? bright : dim;
    for (int c = 0; c < 4; ++c) ASSERT_FLOAT_EQ(cloud.colors[k * 4 + c], expect[c]);
  }
  // Dimmed is the same hue at 45% value; neighbouring maps differ.
  piece_color(0, false, bright);
  piece_color(0, true, dim);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(dim[c], 0.45f * bright[c], 1e-6);
  float next[4];
  piece_color(1, false, next);
  EXPECT_GT(std::abs(next[0] - bright[0]) + std::abs(next[1] - bright[1]) + std::abs(next[2] - bright[2]), 0.3);
}

TEST(PreviewCloud, CollageFramesAreTheBoxAndItsImages) {
  PreviewOptions o;
  o.count = 100000;
  const Ifs s = weighted_sierpinski();
  const PreviewCloud cloud = preview_cloud(s, o);
  // A rectangle has 4 edges of 2 end points: the box, then one frame per map.
  ASSERT_EQ(cloud.frame_pieces.size(), 4u * 2 * (s.size() + 1));
  ASSERT_EQ(cloud.frame_positions.size(), cloud.frame_pieces.size() * 3);
  for (std::size_t v = 0; v < cloud.frame_pieces.size(); ++v) {
    const std::uint32_t piece = cloud.frame_pieces[v];
    const double x = cloud.frame_positions[v * 3], y = cloud.frame_positions[v * 3 + 1];
    if (piece == s.size()) {  // corners of the bounding box
      EXPECT_TRUE(x == float(cloud.bounds.lo[0]) || x == float(cloud.bounds.hi[0]));
      continue;
    }
    // w_i(x, y) = (x / 2 + ox, y / 2 + oy) of a box corner.
    const double ox = s.map(piece).b(0), oy = s.map(piece).b(1);
    const double x0 = 0.5 * cloud.bounds.lo[0] + ox, x1 = 0.5 * cloud.bounds.hi[0] + ox;
    const double y0 = 0.5 * cloud.bounds.lo[1] + oy, y1 = 0.5 * cloud.bounds.hi[1] + oy;
    EXPECT_TRUE(std::abs(x - x0) < 1e-6 || std::abs(x - x1) < 1e-6) << x;
    EXPECT_TRUE(std::abs(y - y0) < 1e-6 || std::abs(y - y1) < 1e-6) << y;
  }
  // 3D: a box has 12 edges.
  std::vector<AffineMap> maps;
  for (int i = 0; i < 4; ++i)
    maps.emplace_back(3, std::vector<double>{0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5},
                      std::vector<double>{i == 1 ? 0.5 : 0.0, i == 2 ? 0.5 : 0.0, i == 3 ? 0.5 : 0.0});
  const PreviewCloud tetra = preview_cloud(Ifs("tetra", ChannelLayout("xyz"), maps), o);
  EXPECT_EQ(tetra.frame_pieces.size(), 12u * 2 * 5);
}

TEST(PreviewCloud, RefusesWhatItCannotShow) {
  const Ifs divergent("grow", ChannelLayout("xy"), {AffineMap(2, {1.3, 0, 0, 1.3}, {0, 0})});
  EXPECT_THROW(preview_cloud(divergent), DivergentSystemError);
  PreviewOptions o;
  o.coloring = PreviewColoring::Channels;
  EXPECT_THROW(preview_cloud(weighted_sierpinski(), o), InputError);  // xy has no colour
  o.coloring = PreviewColoring::Auto;
  o.count = 0;
  EXPECT_THROW(preview_cloud(weighted_sierpinski(), o), InputError);
  EXPECT_THROW(parse_name<PreviewColoring>("rainbow"), InputError);
}

TEST(Morph, EndPointsAreTheSystems) {
  const Ifs a = weighted_sierpinski({0.5, 0.25, 0.25});
  const Ifs b("b", ChannelLayout("xy"), {from_params(0.6, 20, false, 1), from_params(0.3, -40, true, -1)}, {0.7, 0.3});
  const Ifs at0 = morph(a, b, 0.0), at1 = morph(a, b, 1.0);
  ASSERT_EQ(at0.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(max_difference(at0.map(i), a.map(i)), 0.0);
    EXPECT_DOUBLE_EQ(at0.probabilities()[i], a.probabilities()[i]);
  }
  // b is padded: its last map repeated, its probability shared.
  EXPECT_EQ(max_difference(at1.map(1), b.map(1)), 0.0);
  EXPECT_EQ(max_difference(at1.map(2), b.map(1)), 0.0);
  EXPECT_NEAR(at1.probabilities()[1], 0.15, 1e-15);
  EXPECT_NEAR(at1.probabilities()[2], 0.15, 1e-15);
}

TEST(Morph, ParametersMoveLinearlyAndAnglesTakeTheShorterArc) {
  const Ifs a("a", ChannelLayout("xy"), {from_params(0.4, 10, false, 0)});
  const Ifs b("b", ChannelLayout("xy"), {from_params(0.8, 50, false, 2)});
  EXPECT_LT(max_difference(morph(a, b, 0.5).map(0), from_params(0.6, 30, false, 1)), 1e-12);
  EXPECT_LT(max_difference(morph(a, b, 0.25).map(0), from_params(0.5, 20, false, 0.5)), 1e-12);
  // 170 degrees to -170 degrees goes through 180, not through 0.
  const Ifs c("c", ChannelLayout("xy"), {from_params(0.5, 170, false, 0)});
  const Ifs d("d", ChannelLayout("xy"), {from_params(0.5, -170, false, 0)});
  EXPECT_LT(max_difference(morph(c, d, 0.5).map(0), from_params(0.5, 180, false, 0)), 1e-12);
}

TEST(Morph, AReflectionPassesThroughAFlatMap) {
  const Ifs a("a", ChannelLayout("xy"), {from_params(0.5, 0, false, 0)});
  const Ifs b("b", ChannelLayout("xy"), {from_params(0.5, 0, true, 0)});
  // F = diag(1, 1 - 2t): the y column shrinks to 0 at t = 1/2, then flips.
  EXPECT_NEAR(morph(a, b, 0.5).map(0).determinant(), 0.0, 1e-15);
  EXPECT_NEAR(morph(a, b, 0.25).map(0).a(1, 1), 0.25, 1e-12);
  EXPECT_NEAR(morph(a, b, 0.75).map(0).a(1, 1), -0.25, 1e-12);
}

TEST(Morph, IsContinuousInT) {
  // The continuity theorem needs coefficients that move continuously: no jumps from angle
  // wrap-around, reflections or the QR decomposition, for random pairs of systems.
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-0.7, 0.7);
  for (int trial = 0; trial < 40; ++trial) {
    const int n = trial % 2 ? 3 : 2;
    auto random_system = [&] {
      std::vector<AffineMap> maps;
      for (int i = 0; i < 3; ++i) {
        std::vector<double> m(n * n), b(n);
        for (auto& v : m) v = u(rng);
        for (auto& v : b) v = u(rng);
        maps.emplace_back(n, m, b);
      }
      return Ifs("r", ChannelLayout(n == 2 ? "xy" : "xyz"), maps, {1, 1, 1});
    };
    const Ifs a = random_system(), b = random_system();
    Ifs previous = morph(a, b, 0.0);
    for (int k = 1; k <= 1000; ++k) {
      const Ifs now = morph(a, b, k / 1000.0);
      for (std::size_t i = 0; i < 3; ++i) ASSERT_LT(max_difference(now.map(i), previous.map(i)), 0.05) << k;
      previous = now;
    }
  }
}

TEST(Morph, PaddingKeepsTheAttractor) {
  const Ifs s = weighted_sierpinski({0.5, 0.25, 0.25});
  const Ifs padded = pad_maps(s, 5);
  ASSERT_EQ(padded.size(), 5u);
  EXPECT_NEAR(padded.probabilities()[2] + padded.probabilities()[3] + padded.probabilities()[4], 0.25, 1e-15);
  const Bounds a = s.attractor_bounds(1 << 16), b = padded.attractor_bounds(1 << 16);
  for (int c = 0; c < 2; ++c) {
    EXPECT_NEAR(a.lo[c], b.lo[c], 1e-3);
    EXPECT_NEAR(a.hi[c], b.hi[c], 1e-3);
  }
  EXPECT_THROW(pad_maps(s, 2), InputError);
}

TEST(Morph, RefusesMismatches) {
  const Ifs s = weighted_sierpinski();
  std::vector<AffineMap> maps = {AffineMap(3, {0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5}, {0, 0, 0})};
  const Ifs cube("cube", ChannelLayout("xyz"), maps);
  EXPECT_THROW(morph(s, cube, 0.5), InputError);
  EXPECT_THROW(morph(s, s, 1.5), InputError);
  EXPECT_THROW(morph(s, s, NAN), InputError);
}
