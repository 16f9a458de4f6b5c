#pragma once
/// @file Exact Euclidean distance transforms on a pixel grid (Felzenszwalb & Huttenlocher,
/// linear time) and the Hausdorff distance of Eq. 12 between two pixel sets; the same
/// transform on a voxel grid for the 3D fit.
#include <cstdint>
#include <vector>

#include "ifsforge/volume/voxel_grid.h"

namespace ifsforge {

/// @brief A set of pixels: row-major, non-zero = in the set.
struct PixelSet {
  int width = 0, height = 0;
  std::vector<std::uint8_t> cells;
  std::size_t count() const;
};

/// @brief A set of voxels laid in space: cell (i, j, k) is cells[(k * ny + j) * nx + i],
/// non-zero = in the set; grid places it (VoxelGrid: cubic voxels on a box).
struct VoxelSet {
  VoxelGrid grid;
  std::vector<std::uint8_t> cells;
  std::size_t count() const;
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * grid.dims[1] + j) * grid.dims[0] + i;
  }
};

/// @brief Per pixel, the squared Euclidean distance (in pixels) to the nearest pixel of `set`;
/// +infinity everywhere when the set is empty.
std::vector<double> squared_distance_transform(const PixelSet& set);

/// @brief Per voxel, the squared Euclidean distance (in voxels) to the nearest voxel of `set`;
/// +infinity everywhere when the set is empty.
std::vector<double> squared_distance_transform(const VoxelSet& set);

/// @brief max over pixels of `from` of the distance to `to` (0 when `from` is empty, +infinity
/// when only `to` is empty). Both sets must have the same size.
double directed_hausdorff(const PixelSet& from, const PixelSet& to);

/// @brief Eq. 12 on the grid: max of the two directed distances, in pixels.
double hausdorff_distance(const PixelSet& a, const PixelSet& b);

}  // namespace ifsforge
