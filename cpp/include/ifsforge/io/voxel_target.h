#pragma once
/// @file A 3D shape to fit (the inverse problem in 3D) as a voxel set: an OpenVDB density or
/// level-set grid, or a triangle mesh voxelised through OpenVDB. OpenVDB stays behind this header.
#include <string>

#include "ifsforge/inverse/distance_transform.h"

namespace ifsforge {

struct VoxelTargetOptions {
  int resolution = 64;  ///< voxels along the shape's longest side
  /// .vdb fog volumes: a voxel is in the shape when its density exceeds this (level sets: inside, < 0).
  double density_threshold = 0.0;
};

/// @brief The shape in `path`, by extension: .vdb (the grid named "density", else the first
/// float grid; a level set's inside or a fog volume's voxels above the threshold), or a mesh
/// (.obj, .ply, .stl, .off: its inside and the voxels its surface passes within half a voxel of
/// their centre, through OpenVDB's mesh-to-level-set) resampled onto
/// cubic voxels, options.resolution along the longest side of the shape's box, in the file's
/// coordinates. FileError when the file cannot be opened; InputError for an unknown extension,
/// a file that is no OpenVDB, a .vdb without a float grid or with a non-uniform transform, or an
/// empty shape.
VoxelSet read_voxel_target(const std::string& path, const VoxelTargetOptions& options = {});

}  // namespace ifsforge
