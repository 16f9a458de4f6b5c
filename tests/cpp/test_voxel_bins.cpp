// Random iteration fills a large voxel table through bins by region (volume/voxel_bins.h): the
// same integer sums as adding each point as it comes, so the same volume, on any thread count.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "ifsforge/io/ifs_json.h"
#include "ifsforge/volume/volume_renderer.h"
#include "instruction_sets.h"
#include "sample_systems.h"

namespace ifsforge {
namespace {

using sample_systems::sample;

// 256^3 and three jobs of points: the tables pass the binning threshold (4 MB) in the first job,
// so the later jobs go through bins, stages and pours; the RGB pyramid's points carry channel
// values.
TEST(VoxelBins, BinnedRandomIterationGivesTheSameVolume) {
  for (const char* name : {"sierpinski_tetrahedron", "volume_sierpinski_pyramid_rgb"}) {
    const Ifs ifs = sample(name);
    std::vector<Volume> volumes;
    for (const char* bins : {"0", "1"})
      for (int threads : {1, 2}) {
        VolumeOptions o;
        o.resolution = 256;
        o.iterations = 2'500'000;
        o.seed = 3;
        o.density = VolumeDensity::Hits;  // the counts themselves
        o.threads = threads;
        setenv("IFSFORGE_VOXEL_BINS", bins, 1);
        volumes.push_back(render_volume(ifs, "ria", o));
        unsetenv("IFSFORGE_VOXEL_BINS");
      }
    EXPECT_GT(volumes[0].size(), 60000u) << name;
    for (std::size_t k = 1; k < volumes.size(); ++k) {
      EXPECT_EQ(volumes[0].keys, volumes[k].keys) << name << " " << k;
      EXPECT_EQ(volumes[0].density, volumes[k].density) << name << " " << k;
      EXPECT_EQ(volumes[0].channels, volumes[k].channels) << name << " " << k;
    }
  }
}

// FNV-1a over a volume's points count, keys, densities and channel values (their bits).
std::uint64_t volume_bytes_digest(const Volume& v) {
  std::uint64_t h = 1469598103934665603ull;
  auto mix = [&](const void* data, std::size_t bytes) {
    for (std::size_t b = 0; b < bytes; ++b) h = (h ^ static_cast<const unsigned char*>(data)[b]) * 1099511628211ull;
  };
  mix(&v.points, sizeof v.points);
  mix(v.keys.data(), v.keys.size() * sizeof(std::uint64_t));
  mix(v.density.data(), v.density.size() * sizeof(float));
  mix(v.channels.data(), v.channels.size() * sizeof(float));
  return h;
}

// The bytes of random iteration's volumes, pinned (issue 34, item 5): the digests are those of
// the renderer before its tables were filled through bins that keep their points from job to
// job (commit 747b584), on any thread count. Binned cases (the tables pass 4 MB) of a plain,
// a coloured and a recurrent system, and the automatic stop (5 jobs in 3 rounds), whose rounds
// read the tables between jobs; on every instruction set (issue 34, item 2: the chain lanes).
TEST(VoxelBins, RandomIterationVolumesKeepTheirBytes) {
  struct Case {
    const char* name;
    int resolution;
    std::uint64_t iterations;
    VolumeDensity density;
    std::uint64_t digest;
  };
  const Case cases[] = {
      {"sierpinski_tetrahedron", 256, 2'500'000, VolumeDensity::Hits, 0xfdb4e7de8fc09575ull},
      {"volume_sierpinski_pyramid_rgb", 256, 2'500'000, VolumeDensity::Binary, 0xda4cea9536dfea2dull},
      {"recurrent_cubes", 256, 2'500'000, VolumeDensity::Hits, 0x5d5ffa65a53a4ea7ull},
      {"recurrent_cubes", 128, 0, VolumeDensity::Hits, 0xd5ecf3d5625f9506ull},
  };
  // Every instruction set the CPU has: the chain lanes (volume/voxel_chains.h) and the one-job loop.
  for (const char* isa : instruction_sets::available())
    for (const Case& c : cases)
      for (int threads : {1, 3}) {
        VolumeOptions o;
        o.resolution = c.resolution;
        o.iterations = c.iterations;
        o.seed = 3;
        o.density = c.density;
        o.threads = threads;
        setenv("IFSFORGE_ISA", isa, 1);
        EXPECT_EQ(volume_bytes_digest(render_volume(sample(c.name), "ria", o)), c.digest)
            << c.name << " " << c.iterations << " points, " << threads << " threads, " << isa;
        unsetenv("IFSFORGE_ISA");
      }
}

}  // namespace
}  // namespace ifsforge
