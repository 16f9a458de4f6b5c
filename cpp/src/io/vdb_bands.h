#pragma once
// The .vdb band writer's bands (src/io only): each band's keys read into leaves of 8^3 voxels
// (pass 1, the file's layout) and its voxels grouped by leaf (pass 2), with the scratch a thread
// keeps between bands.
#include "vdb_trees.h"

#include <array>
#include <cstdint>
#include <ostream>
#include <streambuf>
#include <string>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/io/vdb.h"
#include "vdb_layout.h"

namespace ifsforge::detail {

/// An output stream appending to a buffer: Blosc's blocks go straight into a band's bytes.
class AppendBuffer : public std::streambuf {
 public:
  LargeVector<char>* out = nullptr;

 protected:
  int_type overflow(int_type c) override {
    if (c != traits_type::eof()) out->push_back(static_cast<char>(c));
    return c;
  }
  std::streamsize xsputn(const char* data, std::streamsize n) override {
    out->insert(out->end(), data, data + n);
    return n;
  }
};

/// Voxels whose values are made at once: the next leaves' voxels, up to this many (or one leaf),
/// so that the values' fetches run ahead across leaves.
constexpr std::uint32_t kBatch = 1024;
static_assert(kBatch >= Leaf::SIZE, "a batch holds a leaf");

/// What one thread keeps between bands.
struct BandScratch {
  Volume volume;                          ///< the loader's storage
  std::vector<std::uint32_t> slot;        ///< leaf + 1 of each (y, z) block of the current 8 rows
  std::vector<std::size_t> touched;       ///< the slots to clear at the next 8 rows
  LargeVector<LeafTopology> leaves;       ///< pass 1: the band's leaves
  std::vector<std::uint32_t> start;       ///< pass 2: each leaf's first voxel in by_leaf
  std::vector<std::uint32_t> end;         ///< pass 2: where each leaf's voxels end in by_leaf
  /// Pass 2: the voxels grouped by leaf, each group ascending; sized for the largest band once, and
  /// never cleared (every element is written before it is read).
  ZeroedVector<std::uint32_t> by_leaf;
  float values[kBatch * 3];               ///< a batch of leaves' values
  std::uint16_t halves[kBatch * 3];       ///< the same as halves (openvdb::math::half's bits)
  std::vector<char> chunk;                ///< leaves next to each other in the file, written together
  LargeVector<char> bytes;                ///< Blosc: a band's bytes of one grid
  AppendBuffer append;
  std::ostream blosc{&append};
};

/// Reads a volume's bands (VolumeBandLoader) into leaves of 8^3 voxels.
class BandWriter {
 public:
  BandWriter(const VoxelGrid& grid, std::size_t bands, const VolumeBandLoader& load, int threads)
      : bands_(bands), load_(load), blocks_k_(static_cast<std::size_t>(grid.dims[2]) / 8 + 1),
        blocks_(blocks_k_ * (static_cast<std::size_t>(grid.dims[1]) / 8 + 1)), dims_(grid.dims),
        scratch_(threads) {}

  std::size_t bands() const { return bands_; }
  std::vector<BandScratch>& scratch() { return scratch_; }

  /// Pass 1: band b's leaves (w.leaves, in file order) and the box of its voxels, from its keys
  /// (grouped by 8 rows of x, in any order and repeated within a group: a merge's inputs).
  void topology(std::size_t b, BandScratch& w, openvdb::CoordBBox& box);

  /// Pass 2: band b's voxels (merged: ascending, distinct), grouped by leaf in w.by_leaf (leaf l's
  /// from w.start[l]) for its leaves `leaves` of pass 1 (file order).
  VoxelSpan voxels(std::size_t b, const std::vector<const LeafTopology*>& leaves, BandScratch& w);

 private:
  /// Once per run of keys: inline, its error path apart (called out of line, it was a third of
  /// the plan's time at 2048^3).
  std::array<int, 3> coord(std::uint64_t key, std::size_t b) const {
    const std::array<int, 3> c = VoxelGrid::coord(key);
    if (__builtin_expect(static_cast<std::size_t>(c[0]) / kVolumeBandRows != b || c[0] >= dims_[0] ||
                             c[1] >= dims_[1] || c[2] >= dims_[2], 0))
      outside(c);
    return c;
  }
  [[noreturn]] __attribute__((noinline, cold)) static void outside(const std::array<int, 3>& c) {
    throw InputError("write_vdb: voxel (" + std::to_string(c[0]) + ", " + std::to_string(c[1]) + ", " +
                     std::to_string(c[2]) + ") lies outside its band or the volume's grid");
  }
  static constexpr std::uint64_t kZ = (std::uint64_t(1) << VoxelGrid::kKeyBits) - 1;  ///< a key's z bits
  std::size_t block(const std::array<int, 3>& c) const { return static_cast<std::size_t>(c[1] >> 3) * blocks_k_ + (c[2] >> 3); }
  void prepare(BandScratch& w) const {
    if (w.slot.size() != blocks_) w.slot.assign(blocks_, 0);
  }
  static void clear(BandScratch& w) {
    for (std::size_t t : w.touched) w.slot[t] = 0;
    w.touched.clear();
  }

  std::size_t bands_;
  const VolumeBandLoader& load_;
  std::size_t blocks_k_, blocks_;
  std::array<int, 3> dims_;
  std::vector<BandScratch> scratch_;
};

/// Pass 1: every band's leaves from its keys, in file order, and which are whose.
Layout plan(BandWriter& bands, const ProgressCallback& progress);

}  // namespace ifsforge::detail
