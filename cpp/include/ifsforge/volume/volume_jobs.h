#pragma once
/// @file A volume job result as bytes, for a cluster: what a worker sends back (the sorted
/// voxel sums of its jobs, cut into x-slabs) and the driver merges exactly, slab by slab,
/// reading the bytes in place (VolumeRenderer::run_jobs, VolumeOptions::distribute).
#include <string>
#include <string_view>
#include <vector>

#include "ifsforge/core/varint.h"
#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

/// @brief Compact bytes: a header, a table of x-slabs from the first holding a voxel to the last
/// (slab s holds the voxels whose x index is in [s, s + 1) << VolumeJobsBytes::kSlabShift), then
/// per slab the voxel keys as ascending deltas (runs along z take one byte each) and the integer
/// sums, all as varints. Sums the volume will not read stay behind: hits unless the density is
/// Hits or there are channels (their means divide by hits), mass unless it is Measure (decoded
/// as 1 hit and no mass: the same volume).
std::string encode_volume_jobs(const VolumeJobsResult& result, VolumeDensity density = VolumeDensity::Measure);
/// @brief The same bytes for the sorted, unmerged lists of jobs (consumed), their `points` and
/// deepest level `depth`: merged and encoded slab by slab on `threads` threads, the merged list
/// never built (a worker's task at 1024^3 would fill and zero hundreds of MB for it).
std::string encode_volume_jobs(std::vector<VoxelList>& lists, std::uint64_t points, int depth, VolumeDensity density,
                               int threads);

/// The bytes encode_volume_jobs wrote, read in place: the header and slab table checked at
/// construction, each slab decoded on demand, so that a merge holds a few slabs' voxels at a
/// time instead of every worker's. `bytes` must outlive the object.
class VolumeJobsBytes {
 public:
  /// Voxels of 2^3 = 8 consecutive x indices per slab: 128 slabs at 1024^3.
  static constexpr int kSlabShift = 3;
  /// @brief InputError when the header or the slab table is malformed.
  explicit VolumeJobsBytes(std::string_view bytes);
  std::uint64_t points() const { return points_; }
  int depth() const { return depth_; }
  int channels() const { return channels_; }
  std::uint64_t entries() const { return entries_; }
  /// @brief The slabs in the table are [first_slab(), slabs()); the others are empty.
  std::size_t first_slab() const { return first_; }
  std::size_t slabs() const { return first_ + slabs_.size(); }
  /// @brief Appends slab s's entries to `out` (keys alone when `keys_only`); InputError when
  /// they are malformed, not ascending or outside the slab. s must be in the table.
  void decode(std::size_t s, VoxelList& out, bool keys_only = false) const;
  /// @brief Appends slab s's keys alone to `keys` (checked as decode checks them).
  void decode_keys(std::size_t s, std::vector<std::uint64_t>& keys) const;

 private:
  /// Appends slab s's keys; the reader stands after them.
  VarintReader read_keys(std::size_t s, std::vector<std::uint64_t>& keys) const;
  friend VolumeJobsResult decode_volume_jobs(std::string_view bytes);
  struct Slab {
    std::size_t begin = 0, size = 0;
    std::uint64_t entries = 0;
  };
  std::string_view bytes_;
  std::vector<Slab> slabs_;
  std::size_t first_ = 0;
  std::uint64_t points_ = 0, entries_ = 0;
  int depth_ = 0, channels_ = 0;
  bool extremes_ = false, hits_ = false, mass_ = false;
};

/// @brief A VolumeJobsBytes of each of `results`, checked on `threads` threads (a render's thousands
/// of job results took a core alone before its merge); InputError as the constructor's.
std::vector<VolumeJobsBytes> read_volume_jobs(const std::vector<std::string_view>& results, int threads);

/// @brief The whole result `encode_volume_jobs` wrote; InputError for anything else.
VolumeJobsResult decode_volume_jobs(std::string_view bytes);

/// @brief finish_volume over job results still as bytes: each slab decoded from every part,
/// merged and converted on one of `threads` threads, the decoded voxels never all held.
Volume finish_volume_jobs(const std::vector<VolumeJobsBytes>& parts, const VoxelGrid& grid, const Ifs& ifs,
                          const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads);

/// @brief The same volume given to `sink` band by band (`header`: the volume without its voxels,
/// see empty_volume): each band's slabs decoded from every part, merged and converted on the
/// thread that asks for it, so that no more than a band per thread is ever held.
void give_volume_jobs(const std::vector<VolumeJobsBytes>& parts, const Volume& header, const ChannelQuantizer& quantizer,
                      double total_mass, const VolumeBandSink& sink);

}  // namespace ifsforge
