#pragma once
// The parts of a .vdb file the band writer lays out itself (src/io only): where each leaf of a
// 5-4-3 tree goes, the tree's topology, each grid's head and the file's head, byte for byte as
// OpenVDB's Archive writes them.
#include "vdb_trees.h"

#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/core/pages.h"
#include "vdb_stream.h"

namespace ifsforge::detail {

// The tree every grid here has: a root, internal nodes spanning 4096 and 128 voxels, 8^3 leaves.
using FloatTree = openvdb::FloatTree;
using Leaf = FloatTree::LeafNodeType;
static_assert(Leaf::DIM == 8 && FloatTree::RootNodeType::ChildNodeType::DIM == 4096 &&
                  FloatTree::RootNodeType::ChildNodeType::ChildNodeType::DIM == kVolumeBandRows,
              "the writer lays out OpenVDB's standard 5-4-3 tree");
constexpr int kLeafMaskBytes = Leaf::NodeMaskType::WORD_COUNT * 8;  // 64
constexpr std::size_t kUpperMaskBytes = 32768 / 8, kLowerMaskBytes = 4096 / 8;

/// A leaf's place in the file: its root child (x, y, z >> 12), then its place in that node
/// (x, y, z >> 7 & 31), then in the lower node (x, y, z >> 3 & 15): the order of a depth-first
/// walk of the tree, which is the order OpenVDB writes leaves in.
inline std::uint64_t file_order(std::uint64_t x, std::uint64_t y, std::uint64_t z) {
  return (x >> 12) << 45 | (y >> 12) << 36 | (z >> 12) << 27 | (x >> 7 & 31) << 22 | (y >> 7 & 31) << 17 |
         (z >> 7 & 31) << 12 | (x >> 3 & 15) << 8 | (y >> 3 & 15) << 4 | (z >> 3 & 15);
}
inline openvdb::Coord leaf_origin(std::uint64_t order) {
  auto axis = [&](int root, int upper, int lower) {
    return static_cast<int>((order >> root & 511) << 12 | (order >> upper & 31) << 7 | (order >> lower & 15) << 3);
  };
  return openvdb::Coord(axis(45, 22, 8), axis(36, 17, 4), axis(27, 12, 0));
}
/// The internal nodes holding a leaf (upper: 4096 voxels wide, lower: 128), as its order's prefix.
inline std::uint64_t upper_of(std::uint64_t order) { return order >> 27; }
inline std::uint64_t lower_of(std::uint64_t order) { return order >> 12; }

/// A leaf of the file: its place (file_order of its origin), the mask of its active voxels
/// (bit (x & 7) << 6 | (y & 7) << 3 | (z & 7), as LeafNode's value mask) and their count.
struct LeafTopology {
  std::uint64_t order = 0;
  std::uint64_t mask[8] = {};
  std::uint32_t count = 0;
};

/// The file as planned: every grid's place, the leaves in file order.
struct Layout {
  LargeVector<LeafTopology> leaves;
  LargeVector<std::uint64_t> orders;       ///< leaves[i].order (binary search)
  LargeVector<std::uint64_t> first_value;  ///< active voxels before leaf i
  std::vector<std::vector<std::size_t>> band_leaves;  ///< band b's leaves, in file order
  openvdb::CoordBBox bbox;
  std::uint64_t voxels = 0;
};

/// How a grid's values are stored.
struct Encoding {
  int components = 1;
  bool half = false, blosc = false;
  std::size_t value_bytes() const { return std::size_t(components) * (half ? 2 : 4); }
};

/// @brief Tree::writeTopology of the planned leaves, as a grid of encoding `e` writes it:
/// topology_head (the buffer count, the root's background and its tile and child counts), then
/// topology_nodes (the internal nodes and the leaves' masks), which is the same for every grid
/// of the same e.blosc && !e.half.
std::string topology_head(const Layout& layout, const Encoding& e);
ZeroedVector<char> topology_nodes(const Layout& layout, const Encoding& e);
/// The size of topology_nodes(layout, e), known without making them.
std::size_t topology_nodes_size(const Layout& layout, const Encoding& e);

/// A grid's head: its descriptor, three stream offsets, compression, metadata and transform.
struct GridHead {
  std::string bytes;
  std::size_t offsets_at = 0;  ///< where the offsets (grid, buffers, end) go, once known
};
/// @brief A grid's head as Archive::writeGrid writes it, the metadata with the statistics and
/// delayed-load metadata OpenVDB adds, the offsets zero. `blosc_sizes`: each leaf's Blosc block.
GridHead grid_head(const StreamGrid& g, const Layout& layout, std::uint32_t compression,
                   const std::vector<std::int64_t>& blosc_sizes);

/// Archive::writeHeader's UUID: 36 characters after the magic, versions and offsets flag.
constexpr std::size_t kUuidOffset = 21, kUuidLength = 36;
/// @brief Archive::writeHeader with a UUID of zeros (for the content hash), the file metadata
/// and the grid count.
std::string file_head(const openvdb::MetaMap& meta, std::int32_t grids);

}  // namespace ifsforge::detail
