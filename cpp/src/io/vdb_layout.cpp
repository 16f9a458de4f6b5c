#include "vdb_layout.h"

#include <openvdb/io/Compression.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/io/GridDescriptor.h>

#include <cstring>
#include <sstream>
#include <type_traits>

namespace ifsforge::detail {
namespace {

template <class T>
void put(std::string& out, const T& value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}

/// tools::memUsage of the tree OpenVDB would hold (the file's file_mem_bytes).
template <class TreeT>
std::int64_t memory_of(const Layout& layout) {
  using Root = typename TreeT::RootNodeType;
  using Upper = typename Root::ChildNodeType;
  using Lower = typename Upper::ChildNodeType;
  using LeafT = typename TreeT::LeafNodeType;
  std::uint64_t uppers = 0, lowers = 0;
  for (std::size_t i = 0; i < layout.orders.size(); ++i) {
    uppers += i == 0 || upper_of(layout.orders[i]) != upper_of(layout.orders[i - 1]);
    lowers += i == 0 || lower_of(layout.orders[i]) != lower_of(layout.orders[i - 1]);
  }
  auto internal = [](auto* node) {
    using Node = std::remove_pointer_t<decltype(node)>;
    return Node::NUM_VALUES * sizeof(typename Node::UnionType) + 2 * Node::NodeMaskType::memUsage() + sizeof(openvdb::Coord);
  };
  static const std::uint64_t leaf = LeafT().memUsage();
  return static_cast<std::int64_t>(sizeof(TreeT) + sizeof(Root) + uppers * internal(static_cast<Upper*>(nullptr)) +
                                   lowers * internal(static_cast<Lower*>(nullptr)) + layout.orders.size() * leaf);
}

}  // namespace

std::string topology_head(const Layout& layout, const Encoding& e) {
  std::string out;
  put(out, std::int32_t(1));
  out.append(std::size_t(e.components) * 4, '\0');  // background 0, written as a full value even when half
  std::uint32_t uppers = 0;
  for (std::size_t i = 0; i < layout.leaves.size(); ++i)
    uppers += i == 0 || upper_of(layout.orders[i]) != upper_of(layout.orders[i - 1]);
  put(out, std::uint32_t(0));
  put(out, uppers);
  return out;
}

namespace {
/// The tile values of an internal node of encoding e: none active, all background.
std::string empty_tiles(const Encoding& e) {
  std::string out(1, '\0');
  if (e.blosc && !e.half) {
    std::ostringstream empty;
    const float nothing = 0.0f;
    openvdb::io::bloscToStream(empty, reinterpret_cast<const char*>(&nothing), std::size_t(e.components) * 4, 0);
    out += empty.str();
  }
  return out;
}
}  // namespace

std::size_t topology_nodes_size(const Layout& layout, const Encoding& e) {
  std::size_t uppers = 0, lowers = 0;
  for (std::size_t i = 0; i < layout.leaves.size(); ++i) {
    uppers += i == 0 || upper_of(layout.orders[i]) != upper_of(layout.orders[i - 1]);
    lowers += i == 0 || lower_of(layout.orders[i]) != lower_of(layout.orders[i - 1]);
  }
  const std::size_t tiles = empty_tiles(e).size();
  return uppers * (3 * sizeof(std::int32_t) + 2 * kUpperMaskBytes + tiles) + lowers * (2 * kLowerMaskBytes + tiles) +
         layout.leaves.size() * kLeafMaskBytes;
}

/// Depth first, every internal node (its origin if an upper one, child mask, an empty value
/// mask, its tile values mask-compressed to nothing) and every leaf's value mask, into a buffer
/// of zeros (only the set bytes are written).
ZeroedVector<char> topology_nodes(const Layout& layout, const Encoding& e) {
  const std::string no_tiles = empty_tiles(e);
  ZeroedVector<char> out;
  zeroed_large(out, topology_nodes_size(layout, e));
  char* at = out.data();
  for (std::size_t i = 0; i < layout.leaves.size();) {
    const std::uint64_t upper = upper_of(layout.orders[i]);
    const openvdb::Coord origin = leaf_origin(layout.orders[i]) & ~4095;
    const std::int32_t xyz[3] = {origin.x(), origin.y(), origin.z()};
    at = std::copy_n(reinterpret_cast<const char*>(xyz), sizeof xyz, at);
    char* children = at;
    at += 2 * kUpperMaskBytes;  // the child mask, then the value mask (empty)
    std::size_t end = i;
    for (; end < layout.leaves.size() && upper_of(layout.orders[end]) == upper; ++end) {
      const unsigned n = layout.orders[end] >> 12 & 32767;
      children[n >> 3] = static_cast<char>(children[n >> 3] | 1 << (n & 7));
    }
    at = std::copy(no_tiles.begin(), no_tiles.end(), at);
    for (std::size_t j = i; j < end;) {
      const std::uint64_t lower = lower_of(layout.orders[j]);
      char* leaves = at;
      at += 2 * kLowerMaskBytes;
      std::size_t stop = j;
      for (; stop < end && lower_of(layout.orders[stop]) == lower; ++stop) {
        const unsigned n = layout.orders[stop] & 4095;
        leaves[n >> 3] = static_cast<char>(leaves[n >> 3] | 1 << (n & 7));
      }
      at = std::copy(no_tiles.begin(), no_tiles.end(), at);
      for (std::size_t k = j; k < stop; ++k, at += kLeafMaskBytes) std::memcpy(at, layout.leaves[k].mask, kLeafMaskBytes);
      j = stop;
    }
    i = end;
  }
  return out;
}

GridHead grid_head(const StreamGrid& g, const Layout& layout, std::uint32_t compression,
                   const std::vector<std::int64_t>& blosc_sizes) {
  openvdb::GridBase::Ptr grid = g.grid->copyGrid();
  openvdb::io::DelayedLoadMetadata delayed;
  if (!layout.leaves.empty()) {
    delayed.resizeMask(layout.leaves.size());  // all io::NO_MASK_OR_INACTIVE_VALS
    if (compression & openvdb::io::COMPRESS_BLOSC) {
      delayed.resizeCompressedSize(layout.leaves.size());
      for (std::size_t i = 0; i < blosc_sizes.size(); ++i) delayed.setCompressedSize(i, blosc_sizes[i]);
    }
  }
  grid->insertMeta(openvdb::GridBase::META_FILE_DELAYED_LOAD, delayed);
  grid->insertMeta(openvdb::GridBase::META_FILE_BBOX_MIN, openvdb::Vec3IMetadata(layout.bbox.min().asVec3i()));
  grid->insertMeta(openvdb::GridBase::META_FILE_BBOX_MAX, openvdb::Vec3IMetadata(layout.bbox.max().asVec3i()));
  grid->insertMeta(openvdb::GridBase::META_FILE_MEM_BYTES,
                   openvdb::Int64Metadata(g.components == 3 ? memory_of<openvdb::Vec3STree>(layout)
                                                            : memory_of<openvdb::FloatTree>(layout)));
  grid->insertMeta(openvdb::GridBase::META_FILE_VOXEL_COUNT, openvdb::Int64Metadata(static_cast<std::int64_t>(layout.voxels)));
  grid->insertMeta(openvdb::GridBase::META_FILE_COMPRESSION, openvdb::StringMetadata(openvdb::io::compressionToString(compression)));
  std::ostringstream os;
  openvdb::io::GridDescriptor(g.grid->getName(), g.grid->type(), g.grid->saveFloatAsHalf()).writeHeader(os);
  GridHead head;
  head.offsets_at = static_cast<std::size_t>(os.tellp());
  const std::int64_t offsets[3] = {0, 0, 0};  // known once the topology and the leaves are
  os.write(reinterpret_cast<const char*>(offsets), sizeof offsets);
  os.write(reinterpret_cast<const char*>(&compression), sizeof compression);
  grid->writeMeta(os);
  grid->writeTransform(os);
  head.bytes = os.str();
  return head;
}

/// Archive::writeHeader (the UUID left for the content hash) and the file metadata and grid count.
std::string file_head(const openvdb::MetaMap& meta, std::int32_t grids) {
  std::ostringstream os;
  const std::int64_t magic = openvdb::OPENVDB_MAGIC;
  const std::uint32_t version[3] = {openvdb::OPENVDB_FILE_VERSION, openvdb::OPENVDB_LIBRARY_MAJOR_VERSION,
                                    openvdb::OPENVDB_LIBRARY_MINOR_VERSION};
  os.write(reinterpret_cast<const char*>(&magic), sizeof magic);
  os.write(reinterpret_cast<const char*>(version), sizeof version);
  os.put(1);  // seekable: grid offsets are stored
  os << std::string(kUuidLength, '0');
  meta.writeMeta(os);
  os.write(reinterpret_cast<const char*>(&grids), sizeof grids);
  return os.str();
}

}  // namespace ifsforge::detail
