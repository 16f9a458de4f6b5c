#include "ifsforge/volume/voxel_grid.h"

#include <algorithm>
#include <string>

#include "ifsforge/core/error.h"

namespace ifsforge {

VoxelGrid fit_voxel_grid(const Box3& box, int resolution) {
  if (resolution < 1 || resolution > kMaxVolumeResolution)
    throw InputError("the volume resolution must be 1.." + std::to_string(kMaxVolumeResolution) +
                     " voxels per side, got " + std::to_string(resolution));
  double longest = 0.0;
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(box[a]) || !std::isfinite(box[a + 3]) || box[a + 3] < box[a])
      throw InputError("the volume bounds must be finite numbers with min <= max on every axis "
                       "(xmin ymin zmin xmax ymax zmax)");
    longest = std::max(longest, box[a + 3] - box[a]);
  }
  if (!(longest > 0.0)) throw InputError("the volume bounds enclose nothing: every side has length 0");
  VoxelGrid grid;
  grid.voxel_size = longest / resolution;
  for (int a = 0; a < 3; ++a) {
    grid.origin[a] = box[a];
    // The tolerance keeps a side of exactly n voxels (up to rounding) at n, not n + 1.
    const double n = std::ceil((box[a + 3] - box[a]) / grid.voxel_size - 1e-9 * resolution);
    grid.dims[a] = std::clamp(static_cast<int>(n), 1, resolution);
  }
  return grid;
}

}  // namespace ifsforge
