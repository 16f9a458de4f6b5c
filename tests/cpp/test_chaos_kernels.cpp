// The chaos game's lane kernels compute the same arithmetic on every instruction set: the image
// of the baseline kernel (any x86-64) equals the AVX2 kernel's bit for bit, on any thread count,
// so one binary gives the same bytes on every CPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/render/renderer.h"
#include "sample_systems.h"

namespace ifsforge {
namespace {

using sample_systems::sample;

Raster render_with(const char* isa, const Ifs& ifs, RenderOptions o, int threads) {
  setenv("IFSFORGE_ISA", isa, 1);
  o.threads = threads;
  Raster r = renderer("chaos").render(ifs, o);
  unsetenv("IFSFORGE_ISA");
  return r;
}

Raster render_on(const char* isa, const Ifs& ifs, int threads) {
  RenderOptions o;
  o.width = o.height = 160;
  o.iterations = 1'500'000;
  o.seed = 7;
  if (ifs.spatial_dims() == 3) o.view = View{30, 20};
  return render_with(isa, ifs, o, threads);
}

bool cpu_has_avx2() {
#if defined(__x86_64__)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

bool cpu_has_avx512() {
#if defined(__x86_64__)
  return cpu_has_avx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
#else
  return false;
#endif
}

// Systems of the lane path: 2D with 2 to 8 maps, and a purely spatial 3D one (its depth rides as
// a third lane).
const char* const kLaneSystems[] = {"barnsley_fern", "sierpinski_triangle", "heighway_dragon", "maple_leaf",
                                    "sierpinski_tetrahedron"};

TEST(ChaosKernels, BaselineAndAvx2GiveTheSameBytes) {
  if (!cpu_has_avx2()) GTEST_SKIP() << "this CPU has no AVX2 + FMA: only the baseline kernel runs here";
  for (const char* name : kLaneSystems) {
    const Ifs ifs = sample(name);
    for (int threads : {1, 2}) {
      const Raster base = render_on("baseline", ifs, threads), wide = render_on("avx2", ifs, threads);
      EXPECT_EQ(base.density, wide.density) << name << " on " << threads << " threads";
      EXPECT_EQ(base.depth, wide.depth) << name;
      EXPECT_EQ(base.points, wide.points) << name;
      EXPECT_GT(base.covered(), 100u) << name;
    }
  }
}

// The switch is read on the lane path: an unknown instruction set is refused there (which also
// shows that these systems take the lane kernels the test above compares).
TEST(ChaosKernels, TheLanePathReadsTheForcedInstructionSet) {
  for (const char* name : kLaneSystems) {
    const Ifs ifs = sample(name);
    EXPECT_THROW(render_on("avx512-imaginary", ifs, 1), InputError) << name;
    unsetenv("IFSFORGE_ISA");
  }
}

/// The chaos game of `ifs` with the switch `variable` at 0 and at 1, each on 1, 2 and 3 threads:
/// all six images.
std::vector<Raster> both_ways(const char* variable, const Ifs& ifs, RenderOptions o) {
  std::vector<Raster> images;
  for (const char* value : {"0", "1"})
    for (int threads : {1, 2, 3}) {
      setenv(variable, value, 1);
      o.threads = threads;
      images.push_back(renderer("chaos").render(ifs, o));
      unsetenv(variable);
    }
  return images;
}

// Large images are counted through tiles (points binned by tile, then counted tile by tile): the
// same integer sums as counting each point as it comes, so the same bytes on any thread count.
TEST(ChaosKernels, TiledCountingGivesTheSameBytesAsDirectCounting) {
  RenderOptions o;
  o.width = 4160;  // above the tiling threshold (4096^2 pixels), past 256 tiles: stage lines prefetched
  o.height = 4100;
  o.iterations = 6'000'000;
  const std::vector<Raster> images = both_ways("IFSFORGE_CHAOS_TILES", sample("barnsley_fern"), o);
  for (std::size_t k = 1; k < images.size(); ++k) EXPECT_EQ(images[0].density, images[k].density) << k;
  EXPECT_GT(images[0].covered(), 100000u);
}

// The same on a small, dense image counted through tiles (the threshold lowered for the test):
// five tiles (stages in L1, not prefetched), the last one partial with the trash slot, every bin
// filled and counted many times, points left in the bins and stages at the end, and the densest
// counters wrapped past 255 many times.
TEST(ChaosKernels, TiledCountingOfADenseImageGivesTheSameBytes) {
  RenderOptions o;
  o.width = 640;
  o.height = 480;
  o.iterations = 24'000'000;
  o.seed = 5;
  setenv("IFSFORGE_CHAOS_TILES_FROM", "1", 1);
  const std::vector<Raster> images = both_ways("IFSFORGE_CHAOS_TILES", sample("barnsley_fern"), o);
  unsetenv("IFSFORGE_CHAOS_TILES_FROM");
  for (std::size_t k = 1; k < images.size(); ++k) EXPECT_EQ(images[0].density, images[k].density) << k;
  EXPECT_GT(*std::max_element(images[0].density.begin(), images[0].density.end()), 10000.0f);
  EXPECT_GT(images[0].covered(), 20000u);
}

// A 2D lane render makes its density from the workers' 8-bit counters and their wraps, without
// an accumulator (render/chaos_hits.h); its jobs' results for a cluster go through one. Both
// are the same integer sums: the local image equals the one merged from the jobs' bytes, counted
// through tiles (the threshold lowered: wraps listed per tile) and not (wraps in a 64-bit
// array), on 1, 2 and 3 threads, the densest counters wrapped many times.
TEST(ChaosKernels, LaneCountsWithoutAnAccumulatorGiveItsBytes) {
  const Ifs fern = sample("barnsley_fern");
  RenderOptions o;
  o.width = 640;
  o.height = 480;
  o.iterations = 12'000'000;
  o.seed = 3;
  const Renderer& chaos = renderer("chaos");
  for (const char* tiles : {"0", "1"})
    for (int threads : {1, 2, 3}) {
      setenv("IFSFORGE_CHAOS_TILES_FROM", "1", 1);
      setenv("IFSFORGE_CHAOS_TILES", tiles, 1);
      o.threads = threads;
      const Raster local = chaos.render(fern, o);
      RenderOptions merged = o;
      std::string bytes;
      merged.distribute = [&](std::uint64_t first, std::uint64_t last, int) {
        bytes = chaos.run_jobs(fern, o, first, last);
        return std::vector<std::string_view>{bytes};
      };
      const Raster through_jobs = chaos.render(fern, merged);
      unsetenv("IFSFORGE_CHAOS_TILES");
      unsetenv("IFSFORGE_CHAOS_TILES_FROM");
      EXPECT_EQ(local.density, through_jobs.density) << "tiles " << tiles << ", " << threads << " threads";
      EXPECT_TRUE(local.channels.empty());
      EXPECT_EQ(local.width, 640);
      EXPECT_EQ(local.height, 480);
      EXPECT_GT(*std::max_element(local.density.begin(), local.density.end()), 5000.0f);
    }
}

/// The chaos game of `ifs` counted into wide accumulators per worker (IFSFORGE_CHAOS_NARROW=0)
/// and into narrow counters, each on 1, 2 and 3 threads.
std::vector<Raster> wide_and_narrow(const Ifs& ifs, int width, int height, std::uint64_t iterations) {
  RenderOptions o;
  o.width = width;
  o.height = height;
  o.iterations = iterations;
  o.seed = 11;
  if (ifs.spatial_dims() == 3) o.view = View{30, 20};
  return both_ways("IFSFORGE_CHAOS_NARROW", ifs, o);
}

void expect_same_bytes(const std::vector<Raster>& images, const std::string& name) {
  for (std::size_t k = 1; k < images.size(); ++k) {
    EXPECT_EQ(images[0].density, images[k].density) << name << " " << k;
    EXPECT_EQ(images[0].depth, images[k].depth) << name << " " << k;
    EXPECT_EQ(images[0].channels, images[k].channels) << name << " " << k;
  }
}

// The general path (more than 8 maps, recurrent systems) counts a purely spatial system into
// the lanes' narrow counters: 8-bit hits with carries (2D), 32-bit hits beside depths (3D). The
// same integer sums and maxima as a wide accumulator per worker, so the same bytes on any thread
// count; a 160x120 frame of the 3D systems puts the trash slot and the depth through it too.
TEST(ChaosKernels, NarrowCountersGiveTheBytesOfAWideAccumulator) {
  const Ifs triangle = sample("sierpinski_triangle");
  std::vector<AffineMap> maps;
  for (int copy = 0; copy < 3; ++copy)
    for (std::size_t i = 0; i < triangle.size(); ++i) maps.push_back(triangle.map(i));
  const Ifs nine("triangle x3", triangle.layout(), maps, std::vector<double>(maps.size(), 1.0));
  for (const Ifs& ifs : {nine, sample("recurrent_squares"), sample("menger_sponge"), sample("recurrent_cubes")}) {
    // 3,000,000 points on 19,200 pixels: the busy pixels take far more than 255, bytes wrap.
    const std::vector<Raster> images = wide_and_narrow(ifs, 160, 120, 3'000'000);
    expect_same_bytes(images, ifs.name());
    EXPECT_EQ(images[0].depth.empty(), ifs.spatial_dims() == 2) << ifs.name();
    EXPECT_GT(images[0].covered(), 1000u) << ifs.name();
  }
}

// A 2D system with channels counts 32-bit hits and channel sums per pixel, each sum's wraps
// adding 2^32 to the wide totals: on 16x12 pixels 2,000,000 points give each busy pixel tens of
// thousands of quantised values of up to 2^20, so the sums wrap many times. Three channels' sums
// are added by the chain lanes themselves (chains::Job::records), each instruction set its own
// way: 9e6 points are 3 jobs, which 1 and 2 threads run side by side in the chain lanes, on the
// small image with every instruction set the CPU has (2e6 points are one job: the one-job loop).
TEST(ChaosKernels, ChannelSumsWrapIntoTheSameBytes) {
  for (const char* name : {"colour5d_sierpinski_rgb", "colour5d_fern_hsi", "rgba_carpet"}) {
    const Ifs ifs = sample(name);
    for (const auto& size : {std::pair<int, int>{16, 12}, std::pair<int, int>{160, 120}}) {
      const std::vector<Raster> images = wide_and_narrow(ifs, size.first, size.second, 2'000'000);
      expect_same_bytes(images, name);
      EXPECT_EQ(images[0].channels.size(), images[0].density.size() * (ifs.dim() - 2)) << name;
      EXPECT_GT(images[0].covered(), std::size_t(size.first * size.second / 8)) << name;
    }
    std::vector<Raster> lanes;
    for (const char* isa : {"baseline", "avx2", "avx512"}) {
      if ((std::string(isa) == "avx2" && !cpu_has_avx2()) || (std::string(isa) == "avx512" && !cpu_has_avx512()))
        continue;
      setenv("IFSFORGE_ISA", isa, 1);
      for (Raster& image : wide_and_narrow(ifs, 16, 12, 9'000'000)) lanes.push_back(std::move(image));
      unsetenv("IFSFORGE_ISA");
    }
    expect_same_bytes(lanes, std::string(name) + " (chain lanes, every instruction set)");
  }
}

// The general path's jobs run side by side in the chain lanes, one job per lane: each lane is
// that job's one-job loop (IFSFORGE_CHAOS_CHAINS=0), operation for operation, on every
// instruction set (baseline, AVX2: 4 chains a register, AVX-512: 8) and any thread count, so the
// image is the same bytes. The systems are the
// benchmark's (bench_chaos_paths: 2D with channels, more than 8 maps, recurrent in 2D and 3D),
// a 3D system with a channel (a wide accumulator per worker), the carpet (xy+rgba, 8 maps:
// six dimensions, each lane's coefficients loaded and transposed) and the colour fern (maps of
// their own linear parts, whose zero terms, left out, are zeros in every map, not only the
// first: its first map's a21 is 0, its second's 0.006); 9e6
// points are 3 jobs (on 2 threads a task of 2 and one of 1, which takes the one-job loop),
// 2.1e7 points 6 (on 1 thread, one register of chains and a part of another). Three more
// triangles check the zero terms the lanes leave out (Maps::diagonal, blocked, planar): a sheared one (a shared a
// off the diagonal: only the projection's zero terms go), one whose first offset is -0
// (its diagonal's zero terms kept) and one whose channel enters x in one map only; and a fern
// whose hue takes x in its frond map only (its channels blocked, not by height: Maps::by_height).
TEST(ChaosKernels, ChainLanesGiveTheBytesOfTheOneJobLoop) {
  const Ifs triangle = sample("sierpinski_triangle");
  std::vector<AffineMap> maps;
  for (int copy = 0; copy < 3; ++copy)
    for (std::size_t i = 0; i < triangle.size(); ++i) maps.push_back(triangle.map(i));
  const Ifs nine("triangle x3", triangle.layout(), maps, std::vector<double>(maps.size(), 1.0));
  auto halves = [&](double shear, double first_offset) {  // nine maps, as `nine`: the chain lanes
    std::vector<AffineMap> copies;
    for (int copy = 0; copy < 3; ++copy)
      for (const auto& [x, y] : {std::pair{copy ? 0.0 : first_offset, 0.0}, {0.5, 0.0}, {0.25, 0.5}})
        copies.emplace_back(2, std::vector<double>{0.5, shear, 0.0, 0.5}, std::vector<double>{x, y});
    return Ifs("triangle of halves", triangle.layout(), copies, std::vector<double>(copies.size(), 1.0));
  };
  // Three halves with a gray channel (xy+k) whose first map's x takes no channel term and the
  // second's does: the zero terms the lanes leave out must be zeros in every map (here none go).
  auto channel_in_x = [&] {
    std::vector<AffineMap> copies;
    for (const auto& [x, y, k] : {std::tuple{0.0, 0.0, 0.0}, {0.5, 0.0, 0.1}, {0.25, 0.5, 0.0}})
      copies.emplace_back(3, std::vector<double>{0.5, 0.0, k, 0.0, 0.5, 0.0, 0.0, 0.0, 0.5},
                          std::vector<double>{x, y, 0.25 + x});
    return Ifs("channel in x", ChannelLayout("xy+k"), copies, std::vector<double>(copies.size(), 1.0));
  };
  auto fern_hue_from_x = [&] {
    const Ifs fern = sample("colour5d_fern_hsi");
    std::vector<AffineMap> copies;
    for (std::size_t i = 0; i < fern.size(); ++i) {
      std::vector<double> a = fern.map(i).matrix();
      if (i == 1) a[2 * 5 + 0] = 0.01;  // a20: the hue drifts with x as well
      copies.emplace_back(5, a, fern.map(i).offset());
    }
    return Ifs("fern, hue from x", fern.layout(), copies, fern.probabilities());
  };
  const std::vector<std::pair<Ifs, std::uint64_t>> systems = {
      {sample("colour5d_sierpinski_rgb"), 9'000'000}, {nine, 21'000'000},
      {sample("recurrent_squares"), 9'000'000},       {sample("menger_sponge"), 9'000'000},
      {sample("recurrent_cubes"), 21'000'000},        {sample("volume_tetrahedron_alpha"), 9'000'000},
      {sample("rgba_carpet"), 9'000'000},             {sample("colour5d_fern_hsi"), 9'000'000},
      {halves(0.25, 0.0), 9'000'000},
      {halves(0.0, -0.0), 9'000'000},                {channel_in_x(), 9'000'000},
      {fern_hue_from_x(), 9'000'000}};
  for (const auto& [ifs, iterations] : systems) {
    RenderOptions o;
    o.width = 160;
    o.height = 120;
    o.iterations = iterations;
    o.seed = 5;
    o.skip = 20;
    if (ifs.spatial_dims() == 3) o.view = View{30, 20};
    setenv("IFSFORGE_CHAOS_CHAINS", "0", 1);
    o.threads = 1;
    const Raster reference = renderer("chaos").render(ifs, o);
    unsetenv("IFSFORGE_CHAOS_CHAINS");
    for (const char* isa : {"baseline", "avx2", "avx512"}) {
      if ((std::string(isa) == "avx2" && !cpu_has_avx2()) || (std::string(isa) == "avx512" && !cpu_has_avx512()))
        continue;
      for (int threads : {1, 2}) {
        const Raster lanes = render_with(isa, ifs, o, threads);
        EXPECT_EQ(reference.density, lanes.density) << ifs.name() << " " << isa << " " << threads;
        EXPECT_EQ(reference.depth, lanes.depth) << ifs.name() << " " << isa << " " << threads;
        EXPECT_EQ(reference.channels, lanes.channels) << ifs.name() << " " << isa << " " << threads;
        EXPECT_EQ(reference.points, lanes.points) << ifs.name();
      }
    }
    EXPECT_GT(reference.covered(), 1000u) << ifs.name();
    // The chain lanes read the forced instruction set (as the task of all the jobs starts):
    // these systems do take them.
    EXPECT_THROW(render_with("avx512-imaginary", ifs, o, 1), InputError) << ifs.name();
    unsetenv("IFSFORGE_ISA");
  }
}

}  // namespace
}  // namespace ifsforge
