// The chaos game's lane kernels compute the same arithmetic on every instruction set: the image
// of the baseline kernel (any x86-64) equals the AVX2 kernel's bit for bit, on any thread count,
// so one binary gives the same bytes on every CPU.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/io/ifs_json.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge {
namespace {

Ifs sample(const std::string& name) {
  return read_ifs_json(std::string(IFSFORGE_SOURCE_DIR) + "/samples/systems/" + name + ".json");
}

Raster render_on(const char* isa, const Ifs& ifs, int threads) {
  setenv("IFSFORGE_ISA", isa, 1);
  RenderOptions o;
  o.width = o.height = 160;
  o.iterations = 1'500'000;
  o.threads = threads;
  o.seed = 7;
  if (ifs.spatial_dims() == 3) o.view = View{30, 20};
  Raster r = renderer("chaos").render(ifs, o);
  unsetenv("IFSFORGE_ISA");
  return r;
}

bool cpu_has_avx2() {
#if defined(__x86_64__)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
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

// Large images are counted through tiles (points binned by tile, then counted tile by tile): the
// same integer sums as counting each point as it comes, so the same bytes on any thread count.
TEST(ChaosKernels, TiledCountingGivesTheSameBytesAsDirectCounting) {
  const Ifs fern = sample("barnsley_fern");
  RenderOptions o;
  o.width = 4160;  // above the tiling threshold (4096^2 pixels)
  o.height = 4100;
  o.iterations = 6'000'000;
  std::vector<Raster> images;
  for (const char* tiles : {"0", "1"})
    for (int threads : {1, 2, 3}) {
      setenv("IFSFORGE_CHAOS_TILES", tiles, 1);
      o.threads = threads;
      images.push_back(renderer("chaos").render(fern, o));
      unsetenv("IFSFORGE_CHAOS_TILES");
    }
  for (std::size_t k = 1; k < images.size(); ++k) EXPECT_EQ(images[0].density, images[k].density) << k;
  EXPECT_GT(images[0].covered(), 100000u);
}

}  // namespace
}  // namespace ifsforge
