// The fit's colour and 3D targets: colour rows by least squares (one collage per channel, seed
// Fig. 4.3), the 3D distance transform, the 3D search, and the prepared collage target.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"
#include "ifsforge/inverse/collage.h"
#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/inverse/fit_3d.h"
#include "ifsforge/inverse/fit_color.h"
#include "test_systems.h"

namespace ifsforge {
namespace {

/// The Sierpinski triangle, drawn on the unit square (render.window).
Ifs framed_sierpinski() {
  Ifs ifs("sierpinski", ChannelLayout("xy"),
          {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0}),
           AffineMap(2, {0.5, 0, 0, 0.5}, {0.25, 0.5})});
  RenderDefaults d;
  d.window = {0, 0, 1, 1};
  ifs.set_render_defaults(d);
  return ifs;
}

TEST(FitColor, RecoversTheRowsOfALinearColorField) {
  // A picture whose colour is affine in the position, f(p) = a . p + d per channel, satisfies
  // f(w_i(p)) = c f(p) + g_i . p + o_i exactly with c = 1/2, g_i = A_i^T a - a / 2 and
  // o_i = a . b_i + d / 2: the fit must find rows that close the collage to the pixel's size.
  const int n = 128;
  const Ifs shape = framed_sierpinski();
  Image picture(n, n, 3);
  PixelSet mask{n, n, std::vector<std::uint8_t>(std::size_t(n) * n, 1)};  // the whole square
  const double a[3][2] = {{0.6, 0.2}, {-0.3, 0.5}, {0.1, -0.4}}, base[3] = {0.1, 0.3, 0.6};
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int c = 0; c < 3; ++c)
        picture.at(x, y, c) = static_cast<float>(a[c][0] * (x + 0.5) / n + a[c][1] * (1 - (y + 0.5) / n) + base[c]);
  const ColorFitResult r = fit_color(shape, picture, mask);
  EXPECT_EQ(r.system.layout().text(), "xy+rgb");
  ASSERT_EQ(r.system.size(), 3u);
  EXPECT_GT(r.samples, std::size_t(n) * n);
  for (int c = 0; c < 3; ++c) EXPECT_LT(r.collage_error[c], 0.5 / n) << c;
  for (std::size_t i = 0; i < 3; ++i) {
    const AffineMap& m = r.system.map(i);
    EXPECT_LE(m.contraction_factor(), 0.9 + 1e-12);
    for (int r0 = 0; r0 < 2; ++r0)
      for (int c0 = 0; c0 < 2; ++c0) EXPECT_EQ(m.a(r0, c0), shape.map(i).a(r0, c0));
  }
}

TEST(FitColor, ClampsTheColorContraction) {
  // A colour that doubles from copy to copy asks for c = 2: it is held at max_contraction.
  const int n = 64;
  const Ifs shape = framed_sierpinski();
  Image picture(n, n, 3);
  Rng rng(3, 0);
  for (float& v : picture.pixels) v = static_cast<float>(rng.uniform());
  PixelSet mask{n, n, std::vector<std::uint8_t>(std::size_t(n) * n, 1)};
  ColorFitOptions o;
  o.max_contraction = 0.6;
  const ColorFitResult r = fit_color(shape, picture, mask, o);
  for (const AffineMap& m : r.system.maps()) EXPECT_LE(m.contraction_factor(), 0.6 + 1e-9);
  EXPECT_EQ(r.system.classify(), Classification::Hyperbolic);
}

TEST(FitColor, RefusesBadInput) {
  Image gray(16, 16, 1);
  PixelSet mask{16, 16, std::vector<std::uint8_t>(256, 1)};
  EXPECT_THROW(fit_color(framed_sierpinski(), gray, mask), InputError);
  Image rgb(16, 16, 3);
  EXPECT_THROW(fit_color(framed_sierpinski(), rgb, PixelSet{8, 8, std::vector<std::uint8_t>(64, 1)}), InputError);
  EXPECT_THROW(color_foreground(rgb), InputError);  // uniform: no shape
}

TEST(FitColor, ForegroundIsWhatDiffersFromTheBorder) {
  // Dark blue on black: below any luminance threshold, yet unlike the border.
  Image picture(20, 10, 3);
  for (int y = 3; y < 7; ++y)
    for (int x = 5; x < 15; ++x) picture.at(x, y, 2) = 0.3f;
  const PixelSet s = color_foreground(picture);
  EXPECT_EQ(s.count(), 40u);
  EXPECT_TRUE(s.cells[5 * 20 + 10]);
  EXPECT_TRUE(has_color(picture));
  EXPECT_FALSE(has_color(Image(4, 4, 3)));
}

TEST(Fit3d, DistanceTransformIsExact) {
  VoxelSet s;
  s.grid.dims = {9, 7, 5};
  Rng rng(11, 0);
  s.cells.resize(9 * 7 * 5);
  for (auto& c : s.cells) c = rng.uniform() < 0.04;
  s.cells[s.index(4, 3, 2)] = 1;
  const auto d = squared_distance_transform(s);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 9; ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (int z = 0; z < 5; ++z)
          for (int y = 0; y < 7; ++y)
            for (int x = 0; x < 9; ++x)
              if (s.cells[s.index(x, y, z)]) best = std::min(best, double((x - i) * (x - i) + (y - j) * (y - j) + (z - k) * (z - k)));
        EXPECT_EQ(d[s.index(i, j, k)], best);
      }
}

/// The tetrahedron's attractor on a 2^k grid over [0, 1]^3: exactly its 4^k cells.
VoxelSet tetrahedron_voxels(int k) {
  const int n = 1 << k;
  VoxelSet s;
  s.grid.dims = {n, n, n};
  s.grid.voxel_size = 1.0 / n;
  s.cells.assign(std::size_t(n) * n * n, 0);
  // Cell (i, j, k) is in it when the binary digits of i, j and k never share a 1.
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) s.cells[s.index(x, y, z)] = (x & y) == 0 && (y & z) == 0 && (x & z) == 0;
  return s;
}

TEST(Fit3d, IouOfTheTrueSystemIsOne) {
  const VoxelSet t = tetrahedron_voxels(5);
  EXPECT_EQ(t.count(), 1024u);
  EXPECT_GT(attractor_iou_3d(test_systems::tetrahedron(), t), 0.99);
  EXPECT_THROW(attractor_iou_3d(framed_sierpinski(), t), InputError);
}

TEST(Fit3d, RecoversATetrahedronAndIsIndependentOfThreads) {
  const VoxelSet t = tetrahedron_voxels(5);
  Fit3dOptions o;
  o.raster = 16;
  o.refine_raster = 32;
  o.restarts = 2;
  o.generations = 60;
  o.attractor_generations = 10;
  o.final_generations = 150;
  o.seed = 2;
  o.threads = 1;
  const FitResult one = fit_3d(t, o);
  o.threads = 2;
  const FitResult two = fit_3d(t, o);
  EXPECT_EQ(one.iou, two.iou);
  for (std::size_t i = 0; i < one.system.size(); ++i) {
    EXPECT_EQ(one.system.map(i).matrix(), two.system.map(i).matrix());
    EXPECT_EQ(one.system.map(i).offset(), two.system.map(i).offset());
  }
  EXPECT_EQ(one.system.layout().text(), "xyz");
  EXPECT_GE(one.iou, 0.7);
  EXPECT_NEAR(attractor_iou_3d(one.system, t, 5), one.iou, 0.1);
  for (const double s : one.system.contraction_factors()) EXPECT_LE(s, 0.9 + 1e-9);
}

// The last search starts from corners that, snapped onto the voxel lattice, already draw the
// target exactly: no search ends better, so none runs; a start a few voxels off still searches,
// and stops at the first best whose snapped corners draw the target, before its generations end.
TEST(Fit3d, AStartThatSnapsOntoTheTargetNeedsNoSearch) {
  const VoxelSet t = tetrahedron_voxels(5);
  Fit3dOptions o;
  o.refine_raster = 32;
  o.final_generations = 50;
  const Ifs tetrahedron = test_systems::tetrahedron();  // named: the range-for over a temporary's maps() would dangle
  for (const AffineMap& m : tetrahedron.maps())
    o.start.push_back(AffineMap(3, m.matrix(), {m.offset()[0] + 0.3 / 32, m.offset()[1], m.offset()[2] - 0.2 / 32}));
  const FitResult exact = fit_3d(t, o);
  EXPECT_EQ(exact.iou, 1.0);
  EXPECT_EQ(exact.evaluations, 0u);
  o.start[0].a(0, 0) += 0.7 / 32;  // one corner 0.7 voxels off: its snapped corner is one voxel off
  o.final_generations = 200;
  const FitResult searched = fit_3d(t, o);
  EXPECT_EQ(searched.iou, 1.0);
  // 30 samples a generation (fit_cma_options for 48 corner coordinates): all 200 would be 6,001.
  EXPECT_GT(searched.evaluations, 0u);
  EXPECT_LT(searched.evaluations, 30u * 200 / 2);
}

TEST(Fit3d, RefusesAnEmptyTarget) {
  VoxelSet t = tetrahedron_voxels(3);
  std::fill(t.cells.begin(), t.cells.end(), 0);
  EXPECT_THROW(fit_3d(t, Fit3dOptions()), InputError);
  t.cells.resize(3);
  EXPECT_THROW(fit_3d(t, Fit3dOptions()), InputError);
}

TEST(CollageTarget, ReusedEqualsFresh) {
  PixelSet target{24, 24, std::vector<std::uint8_t>(576)};
  for (int y = 4; y < 20; ++y)
    for (int x = 2; x < 22; ++x) target.cells[y * 24 + x] = (x + y) % 3 != 0;
  const CollageTarget prepared(target);
  for (double t : {0.0, 0.1, 0.3}) {
    Ifs ifs("moved", ChannelLayout("xy"), {AffineMap(2, {0.5, 0, 0, 0.6}, {t, 0}), AffineMap(2, {0.5, 0.1, 0, 0.5}, {0.5, t})});
    // Eq. 12 from scratch: both directed distances transformed afresh.
    const auto maps = pixel_maps(ifs, target_frame(ifs, target, Window{0, 0, 1, 1}));
    const PixelSet collage = collage_pixels(target, maps, 12);
    const CollageReport a = prepared.distance(ifs, Window{0, 0, 1, 1});
    EXPECT_EQ(a.distance_pixels, hausdorff_distance(pad_pixels(target, 12), collage));
    EXPECT_EQ(a.collage_pixels, collage.count());
  }
  EXPECT_THROW(CollageTarget(PixelSet{4, 4, std::vector<std::uint8_t>(16)}), InputError);
}

}  // namespace
}  // namespace ifsforge
