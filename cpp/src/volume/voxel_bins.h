#pragma once
// Random iteration's points binned by the region of the voxel table their voxel hashes to.
// A large table spreads its slots over more memory than the caches hold, so each point's add
// waited for memory; a bin holds a region's points until there are kLinePoints per cache line
// of the region, then the region is read in order (at the bus's pace, not a miss at a time) and
// its points are added while it is in cache. The bins keep their points from job to job (a
// job's million points filled few bins, and draining them all read the whole table each job);
// the renderer drains them before it reads the table. A point reaches its bin through the
// region's stage (8 points, whole cache lines written with streaming stores), as in
// render/chaos_tiles.h: a store straight into one of hundreds of bins fetched the bin's line
// first. The table holds integer sums and is read sorted, so the voxels are the same whatever
// the order of the adds. Private to the volume renderers.
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
  /// Points a bin holds per cache line of its region before the region is filled: each fill
  /// reads (and writes back) the region once, so 4 points share a line's 64 bytes of traffic.
  static constexpr std::size_t kLinePoints = 4;
  static constexpr std::size_t kBinPoints = kLinePoints * kRegionBytes / 64;
  /// Points a region stages before they go to its bin: whole cache lines of 8-word points.
  static constexpr std::size_t kStagePoints = 8;
  /// Points ahead of the one being added whose slot pour() prefetches.
  static constexpr std::size_t kAhead = 16;

  /// Bins of points with `channels` quantised channel values each.
  explicit VoxelBins(int channels) : words_(1 + channels) {}

  /// @brief Bytes of bins per byte of the table they fill (for memory estimates).
  static double bytes_per_table_byte(int channels) {
    return double(kBinPoints) * (1 + channels) * sizeof(std::uint64_t) / double(kRegionBytes);
  }

  /// @brief Whether `table` is filled through bins until drain(): when it is large, unless
  /// IFSFORGE_VOXEL_BINS=0 (tests and benchmarks compare the two). Bins already holding points
  /// go on as they are while the table keeps its size; if it grew, they are drained first and
  /// the regions sized to it anew (each region must stay within L2).
  template <int Channels>
  bool start(VoxelTable& table) {
    if (active_ && table.bytes() == planned_bytes_) return true;
    if (active_) drain<Channels>(table);
    const char* enabled = std::getenv("IFSFORGE_VOXEL_BINS");
    if (enabled && std::strcmp(enabled, "0") == 0) return false;
    bits_ = 0;
    while ((kRegionBytes << bits_) < table.bytes()) ++bits_;
    if (table.bytes() < kBinnedFromBytes || bits_ == 0) return false;
    const std::size_t regions = std::size_t(1) << bits_;
    // The stages after the bins (16-byte aligned at least, as streaming stores need; whole lines
    // from 1 MB up, which start on a 2 MB boundary), then kAhead points that pour() may read.
    const std::size_t words = (regions * (kBinPoints + kStagePoints) + kAhead) * words_;
    if (records_.size() < words) assign_large(records_, words, std::uint64_t(0));
    fill_.resize(regions);
    staged_.resize(regions);
    for (std::size_t r = 0; r < regions; ++r) {
      fill_[r] = bin(r);
      staged_[r] = stage(r);
    }
    planned_bytes_ = table.bytes();
    active_ = true;
    return true;
  }

  /// @brief Bins one hit of voxel `key` with its quantised channel `values` (`Channels` of
  /// them: the bins' channels, known when compiled so that the records' loops unroll).
  template <int Channels>
  void add(VoxelTable& table, std::uint64_t key, const std::uint64_t* values) {
    constexpr int words = 1 + Channels;
    const std::size_t r = (key * VoxelTable::kHash) >> (64 - bits_);  // the top bits of its slot
    std::uint64_t* place = staged_[r];
    place[0] = key;
    for (int c = 1; c < words; ++c) place[c] = values[c - 1];
    staged_[r] = place + words;
    if (staged_[r] == stage(r) + kStagePoints * words) unstage<Channels>(table, r);
  }

  /// @brief Adds what every bin holds to `table` (nothing when the bins are not in use).
  template <int Channels>
  void drain(VoxelTable& table) {
    if (!active_) return;
    active_ = false;
    for (std::size_t r = 0; r < fill_.size(); ++r) {
      pour<Channels>(table, r);
      for (const std::uint64_t* at = stage(r); at != staged_[r]; at += 1 + Channels)
        table.add_hit<Channels>(at[0], at + 1);
      staged_[r] = stage(r);
    }
  }

 private:
  std::uint64_t* bin(std::size_t r) { return records_.data() + r * kBinPoints * words_; }
  std::uint64_t* stage(std::size_t r) { return bin(fill_.size()) + r * kStagePoints * words_; }

  template <int Channels>
  void unstage(VoxelTable& table, std::size_t r) {
    constexpr int words = 1 + Channels;
    stream_lines(fill_[r], stage(r), words);  // 8 points of `words` words: `words` lines
    staged_[r] = stage(r);
    if ((fill_[r] += kStagePoints * words) == bin(r) + kBinPoints * words) pour<Channels>(table, r);
  }

  template <int Channels>
  void pour(VoxelTable& table, std::size_t r) {
    constexpr int words = 1 + Channels;
    // The region is in L2 after warm(); each add's slot is also prefetched kAhead points ahead
    // so that the probes find it in L1. The look-ahead may read past the bin's last point
    // (into the next bin, the stages or the kAhead points of slack that end records_): a stale
    // key costs a useless prefetch, never a wrong add.
    table.warm(r, bits_);
    const std::uint64_t* const end = fill_[r];
    for (const std::uint64_t* at = bin(r); at != end; at += words) {
      table.prefetch(at[kAhead * words]);
      table.add_hit<Channels>(at[0], at + 1);
    }
    fill_[r] = bin(r);
  }

  int words_;
  int bits_ = 0;
  bool active_ = false;             ///< whether the bins may hold points (start() until drain())
  std::size_t planned_bytes_ = 0;   ///< the table's bytes when the regions were sized
  LargeVector<std::uint64_t> records_;
  std::vector<std::uint64_t*> fill_;    ///< the next free place of each region's bin
  std::vector<std::uint64_t*> staged_;  ///< the next free place of each region's stage
};

}  // namespace ifsforge
