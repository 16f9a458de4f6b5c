// The random-iteration volume's chain lanes (volume/voxel_chains.h): up to eight jobs' orbits
// side by side in vector lanes give the one-job loop's points bit for bit, so the volume is the
// same on every instruction set and thread count, for each kind of draw the lanes take.
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

// The Menger sponge's 20 maps, no longer sharing a linear part and no longer diagonal: each
// lane's coefficients come from its map's row (more than eight maps).
Ifs uneven_sponge() {
  const Ifs sponge = sample("menger_sponge");
  std::vector<AffineMap> maps = sponge.maps();
  for (std::size_t i = 0; i < maps.size(); ++i) {
    maps[i].a(0, 0) *= 1.0 - 0.01 * double(i);
    maps[i].a(1, 2) = 0.002 * double(i);
  }
  return Ifs("uneven sponge", sponge.layout(), maps);
}

Volume voxel_lanes_volume(const Ifs& ifs, const char* isa, int threads) {
  VolumeOptions o;
  o.resolution = 64;
  o.iterations = 2'300'000;  // three jobs, the last one shorter than the others
  o.seed = 5;
  o.density = VolumeDensity::Hits;  // the counts themselves
  o.threads = threads;
  setenv("IFSFORGE_ISA", isa, 1);
  Volume v = render_volume(ifs, "ria", o);
  unsetenv("IFSFORGE_ISA");
  return v;
}

// Shared diagonal linear parts (the tetrahedron), more than four maps' offsets drawn from a
// table (the sponges: direct, and with a gray channel), dense maps (the fern), six dimensions
// (the coral's colours), a recurrent system and more than eight maps of their own; baseline
// x86-64 runs the one-job loop, the reference.
TEST(VoxelChains, EveryInstructionSetGivesTheOneJobLoopsVolume) {
  std::vector<Ifs> systems;
  for (const char* name : {"sierpinski_tetrahedron", "menger_sponge", "volume_menger_gray", "volume_fern_3d",
                           "volume_coral_6d", "recurrent_cubes"})
    systems.push_back(sample(name));
  systems.push_back(uneven_sponge());
  for (const Ifs& ifs : systems) {
    const Volume reference = voxel_lanes_volume(ifs, "baseline", 1);
    EXPECT_GT(reference.size(), 1000u) << ifs.name();
    EXPECT_EQ(reference.points, 2'300'000u) << ifs.name();
    for (const char* isa : instruction_sets::available())
      for (int threads : {1, 3}) {
        const Volume v = voxel_lanes_volume(ifs, isa, threads);
        EXPECT_EQ(v.points, reference.points) << ifs.name() << " " << isa << " " << threads;
        EXPECT_EQ(v.keys, reference.keys) << ifs.name() << " " << isa << " " << threads;
        EXPECT_EQ(v.density, reference.density) << ifs.name() << " " << isa << " " << threads;
        EXPECT_EQ(v.channels, reference.channels) << ifs.name() << " " << isa << " " << threads;
      }
  }
}

}  // namespace
}  // namespace ifsforge
