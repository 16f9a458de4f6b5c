#pragma once
// The OpenVDB grids of a volume, shared by the .vdb writer and the iso-surface (src/io only).
#include "vdb_trees.h"

#include <algorithm>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "ifsforge/core/parallel.h"
#include "ifsforge/volume/volume.h"

namespace ifsforge::detail {

inline void initialize() {
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });
}

/// Voxel (i, j, k) is index coordinate (i, j, k); its centre sits at origin + (i + 1/2) h.
inline openvdb::math::Transform::Ptr transform_of(const VoxelGrid& grid) {
  auto transform = openvdb::math::Transform::createLinearTransform(grid.voxel_size);
  transform->postTranslate(openvdb::Vec3d(grid.origin[0] + 0.5 * grid.voxel_size,
                                          grid.origin[1] + 0.5 * grid.voxel_size,
                                          grid.origin[2] + 0.5 * grid.voxel_size));
  return transform;
}

inline openvdb::Coord coord_of(std::uint64_t key) {
  const auto v = VoxelGrid::coord(key);
  return openvdb::Coord(v[0], v[1], v[2]);
}

/// A grid holding value(v) at every voxel v of the volume. Voxels come sorted by (i, j, k), so
/// the voxels of one x-row of leaf nodes (8 values of i) are a contiguous run: rows are filled
/// into new leaves in parallel, then the leaves are added to the tree in row order (the tree
/// is the same whatever the thread count).
template <typename GridT, typename Value>
typename GridT::Ptr make_grid(const Volume& volume, const std::string& name, Value&& value,
                              const ProgressCallback& progress = nullptr) {
  using Leaf = typename GridT::TreeType::LeafNodeType;
  auto grid = GridT::create();
  grid->setName(name);
  grid->setTransform(transform_of(volume.grid));
  if (volume.size() == 0) return grid;
  // Row r holds the voxels with i in [r DIM, (r + 1) DIM).
  const std::uint64_t rows = static_cast<std::uint64_t>(VoxelGrid::coord(volume.keys.back())[0]) / Leaf::DIM + 1;
  std::vector<std::size_t> first(rows + 1);
  for (std::uint64_t r = 0; r <= rows; ++r)
    first[r] = static_cast<std::size_t>(
        std::lower_bound(volume.keys.begin(), volume.keys.end(), VoxelGrid::key(r * Leaf::DIM, 0, 0)) -
        volume.keys.begin());
  // Leaves of one row are found by their (j, k) block.
  const std::uint64_t blocks_j = static_cast<std::uint64_t>(volume.grid.dims[1]) / Leaf::DIM + 1;
  const std::uint64_t blocks_k = static_cast<std::uint64_t>(volume.grid.dims[2]) / Leaf::DIM + 1;
  std::vector<std::vector<std::unique_ptr<Leaf>>> leaves(rows);
  parallel_jobs(rows, 0, [&](std::size_t r, int) {
    std::vector<Leaf*> block(blocks_j * blocks_k, nullptr);
    for (std::size_t v = first[r]; v < first[r + 1]; ++v) {
      const openvdb::Coord ijk = coord_of(volume.keys[v]);
      Leaf*& leaf = block[(ijk.y() / Leaf::DIM) * blocks_k + ijk.z() / Leaf::DIM];
      if (!leaf) {
        leaves[r].push_back(std::make_unique<Leaf>(ijk & ~(Leaf::DIM - 1), grid->background(), false));
        leaf = leaves[r].back().get();
      }
      leaf->setValueOn(Leaf::coordToOffset(ijk), value(v));
    }
  }, progress);
  auto& tree = grid->tree();
  for (auto& row : leaves)
    for (auto& leaf : row) tree.addLeaf(leaf.release());  // the tree owns it from here
  return grid;
}

}  // namespace ifsforge::detail
