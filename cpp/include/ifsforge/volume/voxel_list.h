#pragma once
/// @file Exact, order-free accumulation shared by the volumetric renderers. Every voxel holds
/// integer sums (hits, fixed-point mass, quantised channel values), so merging the partial
/// results of jobs or workers in any order gives the same bytes: this is what keeps every
/// volume independent of the thread count.
#include <cstdint>
#include <functional>
#include <vector>

#include "ifsforge/model/ifs.h"
#include "ifsforge/volume/volume.h"

namespace ifsforge {

/// @brief Fixed-point units of mass: 2^62 units are the whole invariant measure.
constexpr double kVolumeMassUnit = 4611686018427387904.0;

/// @brief Channel values quantised to 2^20 steps of [lo, hi] (clamped), as integers.
class ChannelQuantizer {
 public:
  static constexpr double kSteps = 1048576.0;
  ChannelQuantizer() = default;
  ChannelQuantizer(std::vector<double> lo, std::vector<double> hi);
  int channels() const { return static_cast<int>(lo_.size()); }
  std::uint64_t quantize(int c, double value) const {
    double q = (value - lo_[c]) * scale_[c];
    q = q < 0.0 ? 0.0 : (q > kSteps ? kSteps : q);
    return static_cast<std::uint64_t>(q + 0.5);
  }
  /// @brief The mean value of `hits` quantised values summing to `sum`.
  double mean(int c, std::uint64_t sum, std::uint64_t hits) const {
    const double q = static_cast<double>(sum) / static_cast<double>(hits);
    return scale_[c] > 0.0 ? lo_[c] + q / scale_[c] : lo_[c];
  }
  const std::vector<double>& lo() const { return lo_; }
  const std::vector<double>& hi() const { return hi_; }
  /// @brief Levels per unit of each channel (0 where its range is empty).
  const std::vector<double>& scale() const { return scale_; }

 private:
  std::vector<double> lo_, hi_, scale_;
};

/// Occupied voxels with their integer sums (structure of arrays). Renderers produce lists
/// sorted by key; merging sums entries with equal keys.
struct VoxelList {
  int channels = 0;
  /// hits and mass may be empty (a decoded job result that did not need them): 1 and 0 per entry.
  std::vector<std::uint64_t> keys, hits, mass;
  std::vector<std::uint64_t> sums;  ///< keys.size() * channels
  /// Optional (empty, or kExtremes per voxel): points inside the voxel, each packed as 21-bit
  /// fractions of the voxel. Slot 2a holds the point with the smallest coordinate a, slot
  /// 2a + 1 the one with the largest (packed with axis a most significant, so that plain
  /// integer min and max pick them, ties broken by the other axes): merging keeps the extremes.
  static constexpr int kExtremes = 6;
  std::vector<std::uint64_t> points;

  explicit VoxelList(int channel_count = 0) : channels(channel_count) {}
  std::size_t size() const { return keys.size(); }
  void clear() {
    keys.clear();
    hits.clear();
    mass.clear();
    sums.clear();
    points.clear();
  }
  void reserve(std::size_t entries) {
    keys.reserve(entries);
    hits.reserve(entries);
    mass.reserve(entries);
    sums.reserve(entries * channels);
  }
  void push(std::uint64_t key, std::uint64_t h, std::uint64_t m, const std::uint64_t* s) {
    keys.push_back(key);
    hits.push_back(h);
    mass.push_back(m);
    sums.insert(sums.end(), s, s + channels);
  }
  /// @brief Adds entry `i` of `other` as a new entry.
  void push_from(const VoxelList& other, std::size_t i) {
    // data(), not &sums[...]: sums is empty without channels.
    push(other.keys[i], other.hits[i], other.mass[i], other.sums.data() + i * channels);
    if (!other.points.empty())
      points.insert(points.end(), other.points.begin() + i * kExtremes, other.points.begin() + (i + 1) * kExtremes);
  }
  /// @brief Bytes per entry (for the memory budget).
  static double entry_bytes(int channels) { return 24.0 + 8.0 * channels; }
};

/// @brief Sorts an unsorted list by key and sums entries with equal keys.
void sort_and_reduce(VoxelList& list);

/// @brief One sorted list holding the sums of every (sorted) list, which are consumed.
/// Work is split into a fixed number of x-slabs merged in parallel.
VoxelList merge_voxel_lists(std::vector<VoxelList>& lists, int threads);

/// @brief Merges sorted lists without building the whole: visit(s, merged) for each x-slab of
/// `width` rows that holds voxels (slab s: x in [s, s + 1) * width), on one of `threads`
/// threads, with that slab's sums (a list reused by the thread: read it during the call).
void merge_slabs(const std::vector<VoxelList>& lists, std::uint64_t width, int threads,
                 const std::function<void(std::size_t slab, const VoxelList& merged)>& visit);

/// @brief Turns the sums of sorted lists (consumed) into a volume: entries with equal keys
/// summed, density by `mode` (Measure divides mass by `total_mass`), channel means through
/// `quantizer`, channel metadata from the layout. Merges and converts in one pass.
Volume finish_volume(std::vector<VoxelList>& lists, const VoxelGrid& grid, const Ifs& ifs,
                     const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads);
/// Fills `lists` with the sorted lists of x-slab s of a merge (the keys alone when `keys_only`),
/// slab s's keys all below slab s + 1's.
using SlabLoader = std::function<void(std::size_t s, std::vector<VoxelList>& lists, bool keys_only)>;
/// @brief The same for lists loaded one x-slab at a time (a driver decoding its workers'
/// results): each thread holds one slab's lists, never all of them.
Volume finish_volume(std::size_t slabs, const SlabLoader& load, const VoxelGrid& grid, const Ifs& ifs,
                     const ChannelQuantizer& quantizer, VolumeDensity mode, double total_mass, int threads);
/// @brief Slabs [first, last) of a merge by `load` (of `channels` channels), finished as
/// finish_volume finishes them, into the keys, density and channels of `out` (storage reused
/// from call to call), on the calling thread: a band of a volume given band by band.
VoxelSpan finish_slabs(std::size_t first, std::size_t last, const SlabLoader& load, const ChannelQuantizer& quantizer,
                       VolumeDensity mode, double total_mass, int channels, Volume& out);
/// @brief A volume with no voxels yet: the grid, the density mode and the channels' names,
/// colour model and ranges.
Volume empty_volume(const VoxelGrid& grid, const Ifs& ifs, const ChannelQuantizer& quantizer, VolumeDensity mode);
/// @brief The same for one sorted list.
Volume finish_volume(VoxelList&& list, const VoxelGrid& grid, const Ifs& ifs, const ChannelQuantizer& quantizer,
                     VolumeDensity mode, double total_mass, int threads);

}  // namespace ifsforge
