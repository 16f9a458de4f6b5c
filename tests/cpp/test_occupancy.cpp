// One occupancy rule for voxels and pixels: a cell is occupied when the attractor's measure in
// its interior is positive. Grid-aligned fractals fill exactly their cells, with the default
// grid (the attractor's box, cells aligned to its low corner) and with explicit bounds, for
// every volume renderer and thread count, and for the recursive 2D renderers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_renderer.h"
#include "test_systems.h"

using namespace ifsforge;
using test_systems::menger;
using test_systems::tetrahedron;

namespace {

AffineMap scaled(int dim, double s, const std::vector<double>& t) {
  AffineMap m(dim);
  for (int a = 0; a < dim; ++a) {
    m.a(a, a) = s;
    m.b(a) = t[a];
  }
  return m;
}

/// The sponge's level-k cells: no two coordinates have a ternary 1 at the same digit.
bool in_sponge(int i, int j, int k) {
  for (; i || j || k; i /= 3, j /= 3, k /= 3)
    if ((i % 3 == 1) + (j % 3 == 1) + (k % 3 == 1) >= 2) return false;
  return true;
}

/// The tetrahedron's level-k cells: no binary digit shared by two coordinates.
bool in_tetrahedron(int i, int j, int k) { return !(i & j) && !(i & k) && !(j & k); }

struct OccupancyCase {
  const char* name;
  Ifs (*system)();
  int base;
  bool (*truth)(int, int, int);
};

const OccupancyCase kCases[] = {{"sponge", menger, 3, in_sponge},
                       {"tetrahedron", [] { return tetrahedron(); }, 2, in_tetrahedron}};

std::vector<std::uint64_t> true_cells(const OccupancyCase& c, int side) {
  std::vector<std::uint64_t> keys;
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
      for (int k = 0; k < side; ++k)
        if (c.truth(i, j, k)) keys.push_back(VoxelGrid::key(i, j, k));
  return keys;  // ascending, as Volume::keys
}

Volume render(const OccupancyCase& c, const std::string& algorithm, int k, bool unit_box, int threads, bool fixed_depth = false) {
  VolumeOptions o;
  o.resolution = static_cast<int>(std::lround(std::pow(c.base, k)));
  if (unit_box) o.bounds = Box3{0, 0, 0, 1, 1, 1};
  if (fixed_depth) o.depth = k;
  o.threads = threads;
  return render_volume(c.system(), algorithm, o);
}

}  // namespace

// PRR (automatic and fixed depth), DIA and ETA give exactly the level-k cells, on the default
// grid and on the unit box, with 1 and 2 threads (k = 5 only for PRR: the others test every
// one of the 243^3 voxels or rewrite them, which takes minutes).
TEST(Occupancy, GridAlignedVolumesFillExactlyTheirCells) {
  for (const OccupancyCase& c : kCases)
    for (int k = 1; k <= 5; ++k) {
      const int side = static_cast<int>(std::lround(std::pow(c.base, k)));
      const auto truth = true_cells(c, side);
      ASSERT_EQ(truth.size(), static_cast<std::size_t>(std::lround(std::pow(c.base == 3 ? 20 : 4, k))));
      for (bool unit_box : {false, true})
        for (const char* algorithm : {"prr", "prr-depth", "dia", "eta"}) {
          const std::string name = algorithm;
          if (k == 5 && c.base == 3 && name != "prr" && name != "prr-depth") continue;
          const bool fixed = name == "prr-depth";
          const Volume one = render(c, fixed ? "prr" : name, k, unit_box, 1, fixed);
          const Volume two = render(c, fixed ? "prr" : name, k, unit_box, 2, fixed);
          EXPECT_EQ(one.grid.dims, (std::array<int, 3>{side, side, side}));
          EXPECT_EQ(one.keys == truth, true) << c.name << " k=" << k << " " << name << (unit_box ? " unit box" : " default")
                                             << ": " << one.size() << " voxels, truth " << truth.size();
          EXPECT_EQ(one.keys, two.keys) << c.name << " k=" << k << " " << name << ": threads 1 and 2 differ";
        }
    }
}

// The chaos game at its default point count: no voxel outside the set, at least 99.9% of it
// (k <= 4: at 243^3 the sponge takes tens of millions of points), the same with 1 and 2 threads.
TEST(Occupancy, RandomIterationStaysInsideTheSetAndFindsIt) {
  for (const OccupancyCase& c : kCases)
    for (int k = 1; k <= 4; ++k) {
      const int side = static_cast<int>(std::lround(std::pow(c.base, k)));
      const auto truth = true_cells(c, side);
      for (bool unit_box : {false, true}) {
        const Volume one = render(c, "ria", k, unit_box, 1);
        const Volume two = render(c, "ria", k, unit_box, 2);
        EXPECT_TRUE(std::includes(truth.begin(), truth.end(), one.keys.begin(), one.keys.end()))
            << c.name << " k=" << k << ": a voxel outside the set";
        EXPECT_GE(static_cast<double>(one.size()), 0.999 * static_cast<double>(truth.size())) << c.name << " k=" << k;
        EXPECT_EQ(one.keys, two.keys);
      }
    }
}

namespace {

/// x -> x / 3 + t in the plane.
Ifs thirds(const std::string& name, const std::vector<std::array<int, 2>>& corners) {
  std::vector<AffineMap> maps;
  for (const auto& t : corners) maps.push_back(scaled(2, 1.0 / 3, {t[0] / 3.0, t[1] / 3.0}));
  return Ifs(name, ChannelLayout("xy"), maps, std::vector<double>(corners.size(), 1.0));
}

Ifs carpet() {
  std::vector<std::array<int, 2>> corners;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != 1 || j != 1) corners.push_back({i, j});
  return thirds("carpet", corners);
}

Ifs cantor_dust() { return thirds("cantor dust", {{0, 0}, {2, 0}, {0, 2}, {2, 2}}); }

/// Pixel (x, y) of a 3^k image: both sets are symmetric under the image's y flip.
bool in_carpet(int x, int y) {
  for (; x || y; x /= 3, y /= 3)
    if (x % 3 == 1 && y % 3 == 1) return false;
  return true;
}

bool in_dust(int x, int y) {
  for (; x || y; x /= 3, y /= 3)
    if (x % 3 == 1 || y % 3 == 1) return false;
  return true;
}

}  // namespace

// 2D: PRR (automatic and fixed depth), TSA and string rewriting plot a leaf at the image of
// its box's centre, so the carpet at 3^k pixels covers exactly its 8^k pixels and the Cantor
// dust its 4^k, with the default window and with the unit square.
TEST(Occupancy, GridAlignedImagesFillExactlyTheirPixels) {
  struct Plane {
    Ifs system;
    bool (*truth)(int, int);
  };
  const Plane planes[] = {{carpet(), in_carpet}, {cantor_dust(), in_dust}};
  for (const Plane& plane : planes)
    for (int k = 1; k <= 5; ++k) {
      const int side = static_cast<int>(std::lround(std::pow(3, k)));
      for (bool unit_window : {false, true})
        for (const char* algorithm : {"prr", "tsa", "string-rewriting"})
          for (int depth : {0, k}) {
            RenderOptions o;
            o.width = o.height = side;
            if (unit_window) o.window = Window{0, 0, 1, 1};
            o.depth = depth;
            o.threads = 2;
            const Raster r = renderer(algorithm).render(plane.system, o);
            int wrong = 0, covered = 0;
            for (int y = 0; y < side; ++y)
              for (int x = 0; x < side; ++x) {
                const bool on = r.density[std::size_t(y) * side + x] > 0.0f;
                covered += on;
                wrong += on != plane.truth(x, y);
              }
            EXPECT_EQ(wrong, 0) << plane.system.name() << " k=" << k << " " << algorithm << " depth " << depth
                                << (unit_window ? " unit window" : " default window") << ": " << covered << " pixels";
          }
    }
}
