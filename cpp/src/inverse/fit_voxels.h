#pragma once
// The 3D fit's raster: the target's voxel grid at the search's resolution, the collage proxy
// of Eq. 41 in 3D and the attractor's overlap (the 2D ones of fit_raster.h, one axis more).
#include <array>
#include <cstdint>
#include <vector>

#include "ifsforge/inverse/distance_transform.h"
#include "ifsforge/model/affine_map.h"

namespace ifsforge {

/// A spatial map in the voxel coordinates of a grid: q = M p + t, row-major [M | t].
using VoxelMap = std::array<double, 12>;

/// The target's box seen through cubic cells, `raster` along its longest side.
struct FitVoxelGrid {
  VoxelGrid grid;

  static FitVoxelGrid for_target(const VoxelSet& full, int raster);
  /// Max-pooled: a cell is set when any target voxel's centre lies in it (thin parts survive).
  VoxelSet downsample(const VoxelSet& full) const;
  VoxelMap voxel_map(const AffineMap& m) const;
};

/// The Chamfer form of the collage distance in 3D (mean instead of max), plus the copies' overlap.
class VoxelCollageProxy {
 public:
  struct Scratch {
    std::vector<std::uint16_t> stamp;
    std::vector<std::uint8_t> hits;
    VoxelSet collage;
  };
  VoxelCollageProxy(const VoxelSet& target, double overlap_weight);
  double operator()(const std::vector<VoxelMap>& maps, Scratch& scratch) const;
  /// Mean distance (voxels) from the target's image under one map to the target.
  double copy_outside(const VoxelMap& map) const;

 private:
  /// The padded grid's cell of the image of sample p under m (clamped onto its border).
  std::size_t padded_cell(const VoxelMap& m, const std::array<float, 3>& p) const;
  VoxelSet target_;
  int pad_;
  std::array<int, 3> padded_;
  double overlap_weight_;
  std::vector<double> distance_to_target_;
  std::vector<std::array<float, 3>> samples_;  ///< 2 x 2 x 2 sub-voxel samples of the target
  std::vector<std::uint32_t> target_cells_;
};

/// Intersection over union of the chaos game's attractor with `target` (maps in its voxel
/// coordinates); points leaving the grid count against it.
double chaos_iou_3d(const std::vector<VoxelMap>& maps, const std::vector<double>& probabilities, const VoxelSet& target,
                    std::uint64_t seed, VoxelCollageProxy::Scratch& scratch);

}  // namespace ifsforge
