#pragma once
// A .vdb written band by band (src/io only): the file OpenVDB's own writer makes for the same
// grids, without building them. OpenVDB still writes the parts it owns (descriptors, metadata,
// transforms); the tree (topology and leaf buffers of a 5-4-3 tree) is written here, leaf by
// leaf at its place in the file, so a volume never has to be held whole, in any form.
#include "vdb_trees.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "ifsforge/io/vdb.h"

namespace ifsforge::detail {

/// One grid of the file: an empty OpenVDB grid carrying its name, class, transform, vector type
/// and half flag, and how its values are made (`components` floats per voxel, 1 or 3).
struct StreamGrid {
  openvdb::GridBase::Ptr grid;
  int components = 1;
  /// The values of `count` voxels of `band` (indices into it, in that order): count * components
  /// floats. Called per leaf, so that they are made where they are written.
  std::function<void(const VoxelSpan& band, const std::uint32_t* voxels, std::size_t count, float* values)> values;
  /// Optional, for a grid saved as halves: the bits of openvdb::math::half of each of `values`,
  /// made without them (the colour grid's linear halves, see LinearHalves).
  std::function<void(const VoxelSpan& band, const std::uint32_t* voxels, std::size_t count, std::uint16_t* halves)> halves;
  /// Set: every voxel's value (a binary density: 1 in every voxel by definition, not read from the
  /// volume). When every grid has one, the bands' voxels are never loaded, only their keys.
  std::optional<float> constant;
};

/// Writes the grids of a volume on `voxel_grid` of `bands` bands (`load`, see VolumeBandLoader) to `path`:
/// the bytes OpenVDB's io::File writes for those grids filled with the same voxels and file
/// metadata `meta`, with the compression `compression` (COMPRESS_ACTIVE_MASK, optionally
/// COMPRESS_BLOSC), except the file's UUID, which is hashed from the content. Atomic;
/// FileError when it cannot write; `threads` (0: every core) never change the bytes; Cancelled when `progress` returns false. Returns the voxels
/// written.
std::uint64_t write_vdb_bands(const std::string& path, const VoxelGrid& voxel_grid, const openvdb::MetaMap& meta,
                     const std::vector<StreamGrid>& grids, std::size_t bands, const VolumeBandLoader& load,
                     std::uint32_t compression, int threads, const ProgressCallback& progress);

}  // namespace ifsforge::detail
