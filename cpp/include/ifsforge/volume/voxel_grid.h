#pragma once
/// @file Where a volume sits in the space of an IFS: cubic voxels of one size on an axis-aligned
/// box. Voxel (i, j, k) covers [origin + (i, j, k) h, origin + (i + 1, j + 1, k + 1) h).
#include <array>
#include <cmath>
#include <cstdint>

namespace ifsforge {

/// The largest --res accepted: beyond it even a thin fractal has more voxels than any machine holds.
constexpr int kMaxVolumeResolution = 16384;

/// xmin ymin zmin xmax ymax zmax.
using Box3 = std::array<double, 6>;

struct VoxelGrid {
  std::array<double, 3> origin{0, 0, 0};  ///< world position of voxel (0, 0, 0)'s low corner
  double voxel_size = 1.0;                ///< edge of a (cubic) voxel in world units
  std::array<int, 3> dims{1, 1, 1};       ///< voxels along x, y, z

  /// Voxel keys pack (i, j, k) into 21 bits each, i most significant: sorting keys sorts
  /// voxels by x, then y, then z, so an x-slab of the grid is a contiguous key range.
  static constexpr int kKeyBits = 21;
  static std::uint64_t key(std::uint64_t i, std::uint64_t j, std::uint64_t k) {
    return (i << (2 * kKeyBits)) | (j << kKeyBits) | k;
  }
  static std::array<int, 3> coord(std::uint64_t key) {
    constexpr std::uint64_t mask = (std::uint64_t(1) << kKeyBits) - 1;
    return {static_cast<int>(key >> (2 * kKeyBits)), static_cast<int>((key >> kKeyBits) & mask),
            static_cast<int>(key & mask)};
  }

  double cells() const { return double(dims[0]) * dims[1] * dims[2]; }
  /// Continuous voxel coordinates of a world point along `axis`.
  double to_voxel(const double* world, int axis) const { return (world[axis] - origin[axis]) / voxel_size; }
  /// The key of the voxel holding `world` (x, y, z); false when the point is outside the grid.
  bool voxel_of(const double* world, std::uint64_t& out) const {
    std::int64_t v[3];
    for (int a = 0; a < 3; ++a) {
      // On [0, dims) the floor is the truncation, and a coordinate is in [0, dims) exactly
      // when its floor is (dims is an integer; NaN fails both): no floor() call, which
      // baseline x86-64 (no SSE4.1 round) emulates in a dozen instructions per axis.
      const double u = to_voxel(world, a);
      if (!(u >= 0.0 && u < dims[a])) return false;
      v[a] = static_cast<std::int64_t>(u);
    }
    out = key(v[0], v[1], v[2]);
    return true;
  }
  /// World position of the centre of voxel (i, j, k).
  std::array<double, 3> center(int i, int j, int k) const {
    return {origin[0] + (i + 0.5) * voxel_size, origin[1] + (j + 0.5) * voxel_size,
            origin[2] + (k + 0.5) * voxel_size};
  }
  /// The world box the grid covers.
  Box3 box() const {
    return {origin[0], origin[1], origin[2], origin[0] + dims[0] * voxel_size,
            origin[1] + dims[1] * voxel_size, origin[2] + dims[2] * voxel_size};
  }
};

/// @brief A grid of cubic voxels over `box` with `resolution` voxels along its longest side
/// (the other sides get as many as they need, at least one). InputError for a resolution
/// outside 1..kMaxVolumeResolution or an empty, inverted or non-finite box.
VoxelGrid fit_voxel_grid(const Box3& box, int resolution);

}  // namespace ifsforge
