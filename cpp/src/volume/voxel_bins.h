#pragma once
// Random iteration's points binned by the region of the voxel table their voxel hashes to.
// A large table spreads its slots over more memory than the caches hold, so each point's add
// waited for memory; a bin holds a region's points until there is about one per cache line of
// the region, then the region is read in order (at the bus's pace, not a miss at a time) and
// its points are added while it is in cache. A point reaches its bin through the region's stage
// (8 points, whole cache lines written with streaming stores), as in render/chaos_tiles.h: a
// store straight into one of hundreds of bins fetched the bin's line first. The table holds integer sums and is read sorted,
// so the voxels are the same whatever the order of the adds. Private to the volume renderers.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ifsforge/core/pages.h"
#include "ifsforge/core/stream_lines.h"
#include "voxel_table.h"

namespace ifsforge {

class VoxelBins {
 public:
  /// Tables of at least this many bytes are filled through bins; smaller ones stay in cache.
  static constexpr std::size_t kBinnedFromBytes = std::size_t(4) << 20;
  /// Bytes of table per region: half of a core's L2 on current x86-64.
  static constexpr std::size_t kRegionBytes = std::size_t(256) << 10;
  /// Points a bin holds before its region is filled: one per cache line of the region.
  static constexpr std::size_t kBinPoints = kRegionBytes / 64;
  /// Points a region stages before they go to its bin: whole cache lines of 8-word points.
  static constexpr std::size_t kStagePoints = 8;

  /// Bins of points with `channels` quantised channel values each.
  explicit VoxelBins(int channels) : words_(1 + channels) {}

  /// @brief Whether `table` is filled through bins (regions sized to it now) until drain():
  /// when it is large, unless IFSFORGE_VOXEL_BINS=0 (tests and benchmarks compare the two).
  bool start(const VoxelTable& table) {
    const char* enabled = std::getenv("IFSFORGE_VOXEL_BINS");
    if (enabled && std::strcmp(enabled, "0") == 0) return false;
    bits_ = 0;
    while ((kRegionBytes << bits_) < table.bytes()) ++bits_;
    if (table.bytes() < kBinnedFromBytes || bits_ == 0) return false;
    const std::size_t regions = std::size_t(1) << bits_;
    // The stages after the bins (16-byte aligned at least, as streaming stores need; whole lines
    // from 1 MB up, which start on a 2 MB boundary).
    const std::size_t words = regions * (kBinPoints + kStagePoints) * words_;
    if (records_.size() < words) assign_large(records_, words, std::uint64_t(0));
    fill_.resize(regions);
    staged_.resize(regions);
    for (std::size_t r = 0; r < regions; ++r) {
      fill_[r] = bin(r);
      staged_[r] = stage(r);
    }
    return true;
  }

  /// @brief Bins one hit of voxel `key` with its quantised channel `values`.
  void add(VoxelTable& table, std::uint64_t key, const std::uint64_t* values) {
    const std::size_t r = (key * VoxelTable::kHash) >> (64 - bits_);  // the top bits of its slot
    std::uint64_t* place = staged_[r];
    place[0] = key;
    for (int c = 1; c < words_; ++c) place[c] = values[c - 1];
    staged_[r] = place + words_;
    if (staged_[r] == stage(r) + kStagePoints * words_) unstage(table, r);
  }

  /// @brief Adds what every bin holds to `table`.
  void drain(VoxelTable& table) {
    for (std::size_t r = 0; r < fill_.size(); ++r) {
      pour(table, r);
      for (const std::uint64_t* at = stage(r); at != staged_[r]; at += words_) table.add(at[0], 1, 1, at + 1);
      staged_[r] = stage(r);
    }
  }

 private:
  std::uint64_t* bin(std::size_t r) { return records_.data() + r * kBinPoints * words_; }
  std::uint64_t* stage(std::size_t r) { return bin(fill_.size()) + r * kStagePoints * words_; }

  void unstage(VoxelTable& table, std::size_t r) {
    stream_lines(fill_[r], stage(r), words_);  // 8 points of words_ words: words_ lines
    staged_[r] = stage(r);
    if ((fill_[r] += kStagePoints * words_) == bin(r) + kBinPoints * words_) pour(table, r);
  }

  void pour(VoxelTable& table, std::size_t r) {
    table.warm(r, bits_);
    for (const std::uint64_t* at = bin(r); at != fill_[r]; at += words_) table.add(at[0], 1, 1, at + 1);
    fill_[r] = bin(r);
  }

  int words_;
  int bits_ = 0;
  LargeVector<std::uint64_t> records_;
  std::vector<std::uint64_t*> fill_;    ///< the next free place of each region's bin
  std::vector<std::uint64_t*> staged_;  ///< the next free place of each region's stage
};

}  // namespace ifsforge
