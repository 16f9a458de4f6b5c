#pragma once
/// @file POV-Ray's density file (.df3), read by `density_file df3` in media: a 6-byte header of
/// three big-endian uint16 sizes (x, y, z), then one big-endian unsigned voxel per cell of 8, 16
/// or 32 bits, x fastest, then y, then z. POV-Ray maps the grid onto the unit cube.
#include <string>

#include "ifsforge/volume/volume.h"

namespace ifsforge {

/// @brief Writes the volume's density grid (atomically): every voxel's density divided by the
/// largest one, scaled to the full range of `bits` (8, 16 or 32) and rounded; empty voxels 0.
/// InputError for other bits or a side longer than 65535 voxels; FileError when it cannot write.
void write_df3(const std::string& path, const Volume& volume, int bits = 8);

}  // namespace ifsforge
