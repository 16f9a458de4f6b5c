// The job API a cluster drives: a render whose jobs run in ranges (as on workers), travel as
// bytes and merge in the renderer equals the render run here, bit for bit.
#include <gtest/gtest.h>

#include "ifsforge/core/error.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_jobs.h"
#include "test_systems.h"

namespace ifsforge {
namespace {

/// Cuts [first, last) into `parts` ranges (some possibly empty), as a cluster driver does.
template <typename Run>
auto in_ranges(std::uint64_t first, std::uint64_t last, std::uint64_t parts, Run run) {
  std::vector<decltype(run(first, last))> out;
  for (std::uint64_t k = 0; k < parts; ++k) {
    const std::uint64_t a = first + (last - first) * k / parts, b = first + (last - first) * (k + 1) / parts;
    if (b > a) out.push_back(run(a, b));
  }
  return out;
}

void expect_same(const Volume& a, const Volume& b) {
  EXPECT_EQ(a.keys, b.keys);
  EXPECT_EQ(a.density, b.density);
  EXPECT_EQ(a.channels, b.channels);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.depth, b.depth);
}

TEST(Jobs, VolumeRangesThroughBytesEqualTheLocalVolume) {
  for (const char* algorithm : {"prr", "ria"})
  for (VolumeDensity density : {VolumeDensity::Binary, VolumeDensity::Hits, VolumeDensity::Measure})
  for (bool color : {false, true}) {
    VolumeOptions o;
    o.resolution = 32;
    o.density = density;
    o.iterations = 3u << 20;
    o.seed = 9;
    const Ifs system = test_systems::tetrahedron(color);
    const VolumeRenderer& r = volume_renderer(algorithm);
    const Volume local = r.render(system, o);
    VolumeOptions remote = o;
    std::uint64_t calls = 0;
    remote.distribute = [&](std::uint64_t first, std::uint64_t last) {
      ++calls;
      return in_ranges(first, last, 3, [&](std::uint64_t a, std::uint64_t b) {
        return decode_volume_jobs(encode_volume_jobs(r.run_jobs(system, o, a, b), o.density));
      });
    };
    const Volume merged = r.render(system, remote);
    EXPECT_GT(calls, 0u) << algorithm;
    ASSERT_GT(local.size(), 100u) << algorithm;
    expect_same(local, merged);
  }
}

TEST(Jobs, ImageRangesEqualTheLocalImage) {
  const Ifs system("sierpinski", ChannelLayout("xy"),
                   {AffineMap(2, {0.5, 0, 0, 0.5}, {0, 0}), AffineMap(2, {0.5, 0, 0, 0.5}, {0.5, 0}),
                    AffineMap(2, {0.5, 0, 0, 0.5}, {0.25, 0.5})},
                   {1.0 / 3, 1.0 / 3, 1.0 / 3});
  for (const char* algorithm : {"chaos", "prr"}) {
    RenderOptions o;
    o.width = o.height = 96;
    const Renderer& r = renderer(algorithm);
    const Raster local = r.render(system, o);
    RenderOptions remote = o;
    remote.distribute = [&](std::uint64_t first, std::uint64_t last) {
      return in_ranges(first, last, 5, [&](std::uint64_t a, std::uint64_t b) { return r.run_jobs(system, o, a, b); });
    };
    const Raster merged = r.render(system, remote);
    EXPECT_EQ(local.density, merged.density) << algorithm;
    EXPECT_EQ(local.points, merged.points) << algorithm;
  }
}

TEST(Jobs, RenderersWithoutJobsAndForeignBytesAreRefused) {
  VolumeOptions o;
  o.resolution = 8;
  o.distribute = [](std::uint64_t, std::uint64_t) { return std::vector<VolumeJobsResult>(); };
  EXPECT_THROW(volume_renderer("dia").render(test_systems::tetrahedron(), o), InputError);
  EXPECT_FALSE(renderer("dia").distributable());
  EXPECT_THROW(decode_volume_jobs("not a job"), InputError);
  VolumeJobsResult r;
  r.voxels.keys = {5, 9};
  r.voxels.hits = {1, 2};
  r.voxels.mass = {3, 4};
  std::string bytes = encode_volume_jobs(r);
  EXPECT_EQ(decode_volume_jobs(bytes).voxels.keys, r.voxels.keys);
  bytes.pop_back();
  EXPECT_THROW(decode_volume_jobs(bytes), InputError);
}

}  // namespace
}  // namespace ifsforge
