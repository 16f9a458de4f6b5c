// Random iteration fills a large voxel table through bins by region (volume/voxel_bins.h): the
// same integer sums as adding each point as it comes, so the same volume, on any thread count.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "ifsforge/io/ifs_json.h"
#include "ifsforge/volume/volume_renderer.h"
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

}  // namespace
}  // namespace ifsforge
