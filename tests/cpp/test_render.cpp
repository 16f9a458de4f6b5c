// The 2D renderers: dimensions of known attractors, determinism across threads, bad input.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/recursion.h"
#include "ifsforge/render/box_counting.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/render/tone_map.h"

using namespace ifsforge;

namespace {

AffineMap similarity(double scale, double degrees, double x, double y) {
  const double c = scale * std::cos(degrees * M_PI / 180), s = scale * std::sin(degrees * M_PI / 180);
  return AffineMap(2, {c, -s, s, c}, {x, y});
}

Ifs sierpinski() {
  return Ifs("sierpinski", ChannelLayout("xy"),
             {similarity(0.5, 0, 0, 0), similarity(0.5, 0, 0.5, 0), similarity(0.5, 0, 0.25, 0.5)}, {1, 1, 1});
}

Ifs fern() {
  return Ifs("fern", ChannelLayout("xy"),
             {AffineMap(2, {0, 0, 0, 0.16}, {0, 0}), AffineMap(2, {0.85, 0.04, -0.04, 0.85}, {0, 1.6}),
              AffineMap(2, {0.2, -0.26, 0.23, 0.22}, {0, 1.6}), AffineMap(2, {-0.15, 0.28, 0.26, 0.24}, {0, 0.44})},
             {0.01, 0.85, 0.07, 0.07});
}

Ifs koch() {
  const double third = 1.0 / 3.0;
  return Ifs("koch", ChannelLayout("xy"),
             {similarity(third, 0, 0, 0), similarity(third, 60, third, 0),
              similarity(third, -60, 0.5, std::sqrt(3.0) / 6.0), similarity(third, 0, 2 * third, 0)},
             {1, 1, 1, 1});
}

/// The tetrahedron's four half-size copies, with a gray channel (map i sets gray to i) when asked.
Ifs tetrahedron(bool gray = false) {
  std::vector<AffineMap> maps;
  for (int i = 0; i < 4; ++i) {
    std::vector<double> a{0.5, 0, 0, 0, 0.5, 0, 0, 0, 0.5}, b(3, 0.0);
    if (i) b[i - 1] = 0.5;
    if (gray) {
      a = {0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0};
      b.push_back(double(i));
    }
    maps.emplace_back(gray ? 4 : 3, a, b);
  }
  return Ifs("tetra", ChannelLayout(gray ? "xyz+gray" : "xyz"), maps, {1, 1, 1, 1});
}

RenderOptions size(int n) {
  RenderOptions o;
  o.width = o.height = n;
  return o;
}

}  // namespace

TEST(BoxCounting, SierpinskiTriangleIsLog3OverLog2) {
  const double expected = std::log(3.0) / std::log(2.0);
  for (const char* algorithm : {"prr", "chaos"}) {
    RenderOptions o = size(2048);
    o.binary = true;
    const Raster r = renderer(algorithm).render(sierpinski(), o);
    const double d = box_counting(r).dimension;
    EXPECT_NEAR(d, expected, 0.03 * expected) << algorithm;
  }
}

TEST(BoxCounting, KochCurveIsLog4OverLog3) {
  const double expected = std::log(4.0) / std::log(3.0);
  RenderOptions o = size(2048);
  o.binary = true;
  const Raster r = renderer("prr").render(koch(), o);
  EXPECT_NEAR(box_counting(r).dimension, expected, 0.03 * expected);
}

TEST(BoxCounting, FilledSquareIsTwoAndLineIsOne) {
  std::vector<std::uint8_t> square(256 * 256, 1), line(256 * 256, 0);
  for (int x = 0; x < 256; ++x) line[100 * 256 + x] = 1;
  EXPECT_NEAR(box_counting(square, 256, 256, 1).dimension, 2.0, 1e-9);
  EXPECT_NEAR(box_counting(line, 256, 256, 1).dimension, 1.0, 1e-9);
}

TEST(Determinism, SameBytesForOneAndTwoThreads) {
  for (const char* algorithm : {"chaos", "prr"}) {
    for (const Ifs& s : {sierpinski(), koch()}) {
      RenderOptions o = size(300);
      o.iterations = 3'000'000;
      o.seed = 42;
      o.threads = 1;
      const Raster one = renderer(algorithm).render(s, o);
      o.threads = 2;
      const Raster two = renderer(algorithm).render(s, o);
      EXPECT_EQ(one.density, two.density) << algorithm;
      o.seed = 43;
      if (std::string(algorithm) == "chaos") {
        EXPECT_NE(renderer(algorithm).render(s, o).density, one.density);
      }
    }
  }
}

TEST(Determinism, ColorChannelsAcrossThreads) {
  // A 2D + gray system: each map sets gray to a constant, so every pixel's mean is exact.
  std::vector<AffineMap> maps;
  const double corners[3][2] = {{0, 0}, {0.5, 0}, {0.25, 0.5}};
  for (int i = 0; i < 3; ++i)
    maps.emplace_back(3, std::vector<double>{0.5, 0, 0, 0, 0.5, 0, 0, 0, 0}, std::vector<double>{corners[i][0], corners[i][1], double(i)});
  const Ifs s("gray", ChannelLayout("xy+gray"), maps, {1, 1, 1});
  RenderOptions o = size(128);
  o.window = Window{0, 0, 1, 1};
  o.iterations = 500'000;
  o.threads = 1;
  const Raster one = renderer("chaos").render(s, o);
  o.threads = 2;
  const Raster two = renderer("chaos").render(s, o);
  EXPECT_EQ(one.channels, two.channels);
  // The bottom-left corner pixel is reached only through map 0: gray = 0 there.
  EXPECT_GT(one.density[127 * 128 + 0], 0.0f);
  EXPECT_NEAR(one.channels[127 * 128 + 0], 0.0f, 1e-5);
  EXPECT_NEAR(one.channels[127 * 128 + 127], 1.0f, 1e-5);  // bottom-right: map 1
}

TEST(Renderers, ChaosGameLosesNoPoint) {
  // Every plotted point lands in exactly one pixel when the window holds the attractor, on the
  // AVX2 lanes (2D, and 3D with depth) and the general path (a colour channel) alike. The 2D
  // lanes count in bytes with carries: pixels here take hundreds of hits.
  RenderOptions o = size(257);
  o.iterations = 3'000'001;
  o.window = Window{-0.1, -0.1, 1.1, 1.1};
  const Raster flat = renderer("chaos").render(sierpinski(), o);
  double total = 0;
  for (float d : flat.density) total += d;
  EXPECT_EQ(total, static_cast<double>(flat.points));
  EXPECT_GE(flat.points, o.iterations);
  EXPECT_GT(*std::max_element(flat.density.begin(), flat.density.end()), 512.0f);  // > 256 on a worker
  o.window.reset();
  o.view = View{30, 20};
  for (bool gray : {false, true}) {
    const Raster solid = renderer("chaos").render(tetrahedron(gray), o);
    total = 0;
    for (float d : solid.density) total += d;
    EXPECT_EQ(total, static_cast<double>(solid.points)) << gray;
  }
}

TEST(Renderers, ChaosGameIn3DKeepsTheNearestDepthOnAnyThreadCount) {
  // The 3D lanes carry the depth towards the viewer as a third pixel-space coordinate: the
  // z-buffer must match PRR's (which takes the largest depth of its leaves) and not depend on
  // the threads.
  RenderOptions o = size(200);
  o.view = View{30, 20};
  o.iterations = 8'000'000;
  o.threads = 1;
  const Raster one = renderer("chaos").render(tetrahedron(), o);
  o.threads = 2;
  const Raster two = renderer("chaos").render(tetrahedron(), o);
  EXPECT_EQ(one.density, two.density);
  EXPECT_EQ(one.depth, two.depth);
  const Raster exact = renderer("prr").render(tetrahedron(), o);
  std::size_t both = 0, either = 0, close = 0;
  for (std::size_t p = 0; p < one.density.size(); ++p) {
    const bool a = one.density[p] > 0, b = exact.density[p] > 0;
    either += a || b;
    if (!(a && b)) continue;
    ++both;
    close += std::abs(one.depth[p] - exact.depth[p]) < 2 * exact.pixel_size;
  }
  EXPECT_GT(double(both) / double(either), 0.98);
  EXPECT_GT(double(close) / double(both), 0.98);
}

TEST(Renderers, PrrFixedDepthPlotsNToTheL) {
  RenderOptions o = size(64);
  o.depth = 5;
  const Raster r = renderer("prr").render(sierpinski(), o);
  EXPECT_EQ(r.points, 243u);  // 3^5 leaves, all on the image
  double total = 0;
  for (float d : r.density) total += d;
  EXPECT_NEAR(total, 1.0, 1e-5);  // the measure is a probability
}

TEST(Recursion, PiecesAreImagesOfTheInvariantBoxWhenItIsTight) {
  // The Sierpinski triangle's box [0, 1]^2 is invariant: B exactly, no margin.
  RecursionPlan plan = plan_recursion(sierpinski(), 0, 8);
  for (int c = 0; c < 2; ++c) {
    EXPECT_DOUBLE_EQ(plan.center[c], 0.5);
    EXPECT_NEAR(plan.half[c], 0.5, 1e-11);
  }
  // The fern's rotations make its invariant box half as wide again as the fern: the sampled
  // box grown by kPieceBoxMargin instead, which holds every point of the attractor.
  plan = plan_recursion(fern(), 0, 8);
  const Bounds b = fern().attractor_bounds(1u << 16);
  for (int c = 0; c < 2; ++c)
    EXPECT_NEAR(plan.half[c], (0.5 + kPieceBoxMargin) * (b.hi[c] - b.lo[c]), 1e-9);
}

TEST(Renderers, PrrStopsAtPiecesThatFitAPixel) {
  // At 2^9 pixels the depth-9 pieces of the Sierpinski triangle are one pixel wide, on pixel
  // edges or half a pixel off them: each is one leaf of one or two deposits (a margin around B
  // made every one of them wider than a pixel, and the tree went a level deeper). Each pixel
  // holds 1 or 1/2 of a piece's mass 3^-9, the exact invariant measure of the pixel.
  const Raster r = renderer("prr").render(sierpinski(), size(512));
  EXPECT_LE(r.points, 2u * 19683u);
  const double piece = std::pow(3.0, -9);
  std::size_t covered = 0;
  double total = 0;
  for (float d : r.density) {
    if (d == 0.0f) continue;
    ++covered;
    total += d;
    const double halves = 2.0 * d / piece;
    EXPECT_NEAR(halves, std::round(halves), 1e-4);
  }
  EXPECT_EQ(covered, 26244u);  // 4/3 of 3^9
  EXPECT_NEAR(total, 1.0, 1e-5);
}

TEST(Renderers, RefuseBadInput) {
  setenv("IFSFORGE_MEMORY_BUDGET_MB", "256", 1);
  Ifs divergent("div", ChannelLayout("xy"), {similarity(1.5, 0, 0, 0), similarity(1.2, 30, 1, 0)});
  for (const Renderer* r : renderers()) {
    if (r->name() == "color-stealing" || r->name() == "tops") continue;  // need a reference picture
    EXPECT_THROW(r->render(divergent, size(16)), DivergentSystemError) << r->name();
    EXPECT_THROW(r->render(sierpinski(), size(0)), InputError) << r->name();
    RenderOptions huge = size(20000);
    // One grid: a default supersample of 2 would be refused earlier, as too many cells.
    for (const auto& p : r->parameters())
      if (p.name == "supersample") huge.parameters["supersample"] = "1";
    EXPECT_THROW(r->render(sierpinski(), huge), MemoryBudgetError) << r->name();
  }
  unsetenv("IFSFORGE_MEMORY_BUDGET_MB");
  EXPECT_THROW(renderer("no-such-algorithm"), InputError);
}

TEST(Renderers, ProgressCanCancel) {
  RenderOptions o = size(256);
  o.iterations = 50'000'000;
  o.progress = [&](double) { return false; };
  EXPECT_THROW(renderer("chaos").render(sierpinski(), o), Cancelled);
}

TEST(Parallel, CancellingReachesInsideALongJob) {
  // One job that would run for a minute unless it sees the stop: the caller's callback, not
  // the end of the job, decides when the work ends.
  bool saw_stop = false;
  int calls = 0;
  auto job = [&](std::size_t, int) {
    for (int k = 0; k < 60000 && !saw_stop; ++k) {
      if (stop_requested()) saw_stop = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (saw_stop) throw Cancelled();
  };
  EXPECT_THROW(parallel_jobs(1, 2, job, [&](double) { return ++calls < 3; }), Cancelled);
  EXPECT_TRUE(saw_stop);
  EXPECT_EQ(calls, 3);
  EXPECT_FALSE(stop_requested());  // outside a job, nothing is stopping
}

TEST(Parallel, KeptThreadsRunEveryJobOnceAcrossCallsNestedCallsAndFailures) {
  // The helper threads live on between calls: each call still runs each job exactly once on
  // workers in [0, threads), a job's own parallel call finishes (no helper waits for a busy one),
  // and a failed call leaves the next one whole.
  for (int round = 0; round < 200; ++round) {
    const int threads = 1 + round % 5;
    std::vector<std::atomic<int>> runs(37);
    std::atomic<bool> worker_in_range{true};
    parallel_jobs(runs.size(), threads, [&](std::size_t job, int worker) {
      if (worker < 0 || worker >= threads) worker_in_range = false;
      if (job % 9 == 0) {
        std::atomic<int> inner{0};
        parallel_jobs(5, 3, [&](std::size_t, int) { ++inner; });
        if (inner != 5) return;
      }
      ++runs[job];
    });
    EXPECT_TRUE(worker_in_range);
    for (std::size_t job = 0; job < runs.size(); ++job) ASSERT_EQ(runs[job], 1) << "round " << round << ", job " << job;
    EXPECT_THROW(parallel_jobs(8, threads, [](std::size_t job, int) {
                   if (job == 3) throw InputError("job 3");
                 }),
                 InputError);
  }
}

TEST(Renderers, FixedDepthOverTenToTheTwelveLeavesIsRefusedByName) {
  RenderOptions o = size(64);
  o.depth = 60;
  try {
    renderer("prr").render(sierpinski(), o);
    FAIL() << "3^60 leaves were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("depth: 3^60"), std::string::npos) << e.what();
  }
  o.depth = 25;  // 3^25 = 8.5e11: allowed (cancelled at once here)
  o.progress = [](double) { return false; };
  EXPECT_THROW(renderer("prr").render(sierpinski(), o), Cancelled);
}

TEST(Recursion, BalancedJobsAreACompletePrefixCodeInAddressOrder) {
  // The fern's map 1 holds most of its area: a uniform prefix would give one job over a third of
  // the pixels.
  const Ifs f = fern();
  RecursionPlan plan = plan_recursion(f, 0, 20);
  const Frame frame = Frame::fit(f, 1024, 1024, {}, {});
  auto weight = [&](const AffineMap& m) {
    double lo[2], hi[2];
    piece_pixel_box(frame, plan, m, lo, hi);
    return (hi[0] - lo[0]) * (hi[1] - lo[1]);
  };
  const double root = weight(AffineMap(2));
  balance_jobs(f, plan, weight);
  ASSERT_EQ(plan.addresses.size(), plan.jobs);
  EXPECT_GE(plan.jobs, 64u);
  EXPECT_LE(plan.jobs, 1u << 14);
  double kraft = 0.0, largest = 0.0;
  std::size_t longest = 0;
  for (std::size_t k = 0; k < plan.jobs; ++k) {
    const auto& a = plan.addresses[k];
    kraft += std::pow(4.0, -static_cast<double>(a.size()));  // sums to 1 iff every leaf has one job
    AffineMap piece(2);
    for (std::uint32_t i : a) piece = piece.compose(f.map(i));
    largest = std::max(largest, weight(piece) / root);
    longest = std::max(longest, a.size());
    if (k) {
      const auto& b = plan.addresses[k - 1];
      EXPECT_LT(b, a);  // address order
      EXPECT_FALSE(std::equal(b.begin(), b.end(), a.begin(), a.begin() + std::min(a.size(), b.size())));
    }
  }
  EXPECT_NEAR(kraft, 1.0, 1e-12);
  EXPECT_LE(largest, 1.0 / 256.0 * 1.5);  // a child of a split piece may exceed the bound a little
  EXPECT_GT(longest, 8u);                 // the cut follows map 1 deep
}

TEST(Renderers, PrrMeasureIsTheSameImageOnAnyThreadCountWithBalancedJobs) {
  RenderOptions o = size(512);
  const Raster one = [&] { o.threads = 1; return renderer("prr").render(fern(), o); }();
  o.threads = 2;
  const Raster two = renderer("prr").render(fern(), o);
  EXPECT_EQ(one.density, two.density);
  EXPECT_EQ(one.points, two.points);
  // The pixels the pixel stop's leaves deposit into (a leaf's images merged per pixel), not a
  // fallback to a fixed depth.
  EXPECT_EQ(one.points, 1074759u);
}

TEST(Renderers, PrrJobsSumTheLeavesThatComeToAPixelTogether) {
  // The fern's 512^2 measure puts about 25 leaves on each pixel it covers, most of them from
  // one job close together: a job's result carries a pixel's sum (under a byte per leaf in
  // all), where it carried every leaf (six bytes each) before.
  RenderOptions o = size(512);
  const Renderer& prr = renderer("prr");
  const Raster raster = prr.render(fern(), o);
  std::size_t covered = 0;
  for (float d : raster.density) covered += d > 0.0f;
  ASSERT_GT(raster.points, 20 * covered);
  const std::string bytes = prr.run_jobs(fern(), o, 0, std::uint64_t(1) << 40);
  EXPECT_LT(bytes.size(), raster.points / 2);
  EXPECT_GT(bytes.size(), 3 * covered);  // at least a pixel's step, its leaves and its mass each
}

TEST(ToneMap, HsiPrimaries) {
  float rgb[3];
  hsi_to_rgb(0.0, 1.0, 1.0 / 3.0, rgb);  // pure red has I = 1/3
  EXPECT_NEAR(rgb[0], 1.0f, 1e-6);
  EXPECT_NEAR(rgb[1], 0.0f, 1e-6);
  hsi_to_rgb(1.0 / 3.0, 1.0, 1.0 / 3.0, rgb);
  EXPECT_NEAR(rgb[1], 1.0f, 1e-6);
  hsi_to_rgb(0.5, 0.0, 0.5, rgb);  // no saturation: gray
  EXPECT_NEAR(rgb[0], 0.5f, 1e-6);
  EXPECT_NEAR(rgb[2], 0.5f, 1e-6);
}
