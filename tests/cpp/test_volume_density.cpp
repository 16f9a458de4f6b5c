// Volume densities as measures (seed Eq. 22): the point-recursive and deterministic volumes'
// measure sums to one, random iteration counts its points, and every voxel of a grid-aligned
// tetrahedron holds the product of its address's probabilities.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "ifsforge/volume/volume_renderer.h"
#include "test_systems.h"

using namespace ifsforge;
using namespace ifsforge::test_systems;

namespace {

VolumeOptions measure_options(int resolution, int depth = 0) {
  VolumeOptions o;
  o.resolution = resolution;
  o.depth = depth;
  return o;
}

}  // namespace

TEST(VolumeDensity, MeasureSumsToOneAndHitsCountPoints) {
  VolumeOptions o = measure_options(64);
  o.density = VolumeDensity::Measure;
  const Volume prr = render_volume(tetrahedron(), "prr", o);
  EXPECT_NEAR(std::accumulate(prr.density.begin(), prr.density.end(), 0.0), 1.0, 1e-6);
  const Volume dia = render_volume(tetrahedron(), "dia", o);
  EXPECT_NEAR(std::accumulate(dia.density.begin(), dia.density.end(), 0.0), 1.0, 1e-6);
  o.density = VolumeDensity::Hits;
  o.iterations = 3000000;
  const Volume ria = render_volume(tetrahedron(), "ria", o);
  EXPECT_EQ(ria.points, 3000000u);
  EXPECT_DOUBLE_EQ(std::accumulate(ria.density.begin(), ria.density.end(), 0.0), 3000000.0);
  // The tetrahedron's measure is uniform: each first-level cube holds a quarter of it.
  o.density = VolumeDensity::Measure;
  o.depth = 6;
  o.bounds = Box3{0, 0, 0, 1, 1, 1};
  const Volume aligned = render_volume(tetrahedron(), "prr", o);
  double corner = 0.0;
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    const auto c = VoxelGrid::coord(aligned.keys[i]);
    if (c[0] < 32 && c[1] < 32 && c[2] < 32) corner += aligned.density[i];
  }
  EXPECT_NEAR(corner, 0.25, 1e-9);
}

// Unequal probabilities: a level-k cell of the tetrahedron is the image of the unit cube under
// one address of k maps, and its measure is the product of their probabilities (seed Eq. 22).
// Bit b of a cell's x, y or z coordinate says that map 1, 2 or 3 was taken at level k - b (map 0
// where none is set), so the measure of every voxel is known: at the fixed depth and at the
// automatic one (whose top levels are a precomputed sub-tree), on 1, 2 and 3 threads.
TEST(VolumeDensity, MeasureOfEachCellIsTheProductOfItsAddressProbabilities) {
  const std::vector<double> p = {0.4, 0.3, 0.2, 0.1};
  const Ifs t = tetrahedron();
  const Ifs uneven("uneven tetrahedron", t.layout(), t.maps(), p);
  constexpr int kDepth = 6;
  for (int threads : {1, 2, 3})
  for (int depth : {kDepth, 0}) {
    VolumeOptions o = measure_options(1 << kDepth, depth);
    o.bounds = Box3{0, 0, 0, 1, 1, 1};
    o.density = VolumeDensity::Measure;
    o.threads = threads;
    const Volume v = render_volume(uneven, "prr", o);
    ASSERT_EQ(v.size(), std::size_t(1) << (2 * kDepth));
    double total = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const auto c = VoxelGrid::coord(v.keys[i]);
      double measure = 1;
      for (int b = 0; b < kDepth; ++b)
        measure *= p[(c[0] >> b & 1) ? 1 : (c[1] >> b & 1) ? 2 : (c[2] >> b & 1) ? 3 : 0];
      EXPECT_NEAR(v.density[i], measure, 1e-6 * measure)  // stored in single precision
          << c[0] << " " << c[1] << " " << c[2] << " on " << threads << ", depth " << depth;
      total += v.density[i];
    }
    EXPECT_NEAR(total, 1.0, 1e-6);
  }
}
