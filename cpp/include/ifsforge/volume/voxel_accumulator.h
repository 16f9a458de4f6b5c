#pragma once
/// @file Per-worker accumulation of one job's points: a small dense box of integer sums around
/// the job's piece of the attractor (cache-friendly, no hashing), with a sorted overflow list
/// for points that fall outside it. A job's result is a VoxelList sorted by key.
#include <cmath>
#include <cstdint>
#include <vector>

#include "ifsforge/core/pages.h"
#include "ifsforge/volume/voxel_grid.h"
#include "ifsforge/volume/voxel_list.h"

namespace ifsforge {

class VoxelAccumulator {
 public:
  /// Boxes larger than this many voxels are not allocated: their points go to the overflow list.
  static constexpr std::size_t kMaxBoxCells = std::size_t(1) << 18;

  VoxelAccumulator(const VoxelGrid& grid, const ChannelQuantizer& quantizer);
  /// @brief Bytes one accumulator takes at most (for the memory budget).
  static double bytes(int channels) { return kMaxBoxCells * (16.0 + 8.0 * channels); }

  /// @brief Starts a job whose points are expected in the continuous voxel box [lo, hi].
  void begin(const double* lo, const double* hi);
  /// @brief One point (x, y, z, then the channels) with `mass` (fraction of the whole measure).
  /// Points outside the grid are dropped. With `hit` false only the mass is added: the point
  /// must then have been added before (its voxel counted it and its channels).
  void add(const double* point, double mass, bool hit = true) {
    double u[3];
    for (int a = 0; a < 3; ++a) u[a] = (point[a] - grid_.origin[a]) * inverse_;
    add_voxel(u, point + 3, mass, hit);
  }
  /// @brief The same with the position `u` in continuous voxel coordinates and the channels
  /// apart (unused, and may be null, when `hit` is false).
  void add_voxel(const double* u, const double* channels, double mass, bool hit = true) {
    std::int64_t v[3];
    for (int a = 0; a < 3; ++a) {
      const double f = std::floor(u[a]);
      if (!(f >= 0.0 && f < grid_.dims[a])) return;
      v[a] = static_cast<std::int64_t>(f);
    }
    const std::uint64_t units = static_cast<std::uint64_t>(mass * kVolumeMassUnit + 0.5);
    const std::uint64_t di = v[0] - lo_[0], dj = v[1] - lo_[1], dk = v[2] - lo_[2];
    if (di < size_[0] && dj < size_[1] && dk < size_[2]) {
      // A cell is (hits, mass, channel sums) side by side: one cache line per point.
      const std::size_t index = (di * size_[1] + dj) * size_[2] + dk;
      std::uint64_t* cell = &cells_[index * stride_];
      // Mass alone belongs to a voxel that holds a point (finish() emits and clears only
      // those): see add_mass, which finds one.
      if (!hit && !occupied_[index]) return;
      cell[1] += units;
      if (!hit) return;
      ++cell[0];
      occupied_[index] = 1;
      for (int c = 0; c < channels_; ++c) cell[2 + c] += quantizer_.quantize(c, channels[c]);
      return;
    }
    for (int c = 0; c < channels_; ++c) values_[c] = hit ? quantizer_.quantize(c, channels[c]) : 0;
    overflow_.push(VoxelGrid::key(v[0], v[1], v[2]), hit ? 1 : 0, units, values_.data());
  }
  /// @brief A piece's mass, with no point of its own: at `u` when that voxel holds a point of
  /// the job, else at the first voxel of [first, last] (inclusive, per axis) that does, else
  /// nowhere in the box (a voxel outside the job's box takes it as a list entry). The choice
  /// depends on the job alone, never on what the accumulator held before it.
  void add_mass(const double* u, const std::int64_t* first, const std::int64_t* last, double mass) {
    if (!in_box(u) || occupied_voxel(u)) {
      add_voxel(u, nullptr, mass, false);
      return;
    }
    for (std::int64_t i = std::max(first[0], lo_[0]); i <= last[0] && i - lo_[0] < std::int64_t(size_[0]); ++i)
      for (std::int64_t j = std::max(first[1], lo_[1]); j <= last[1] && j - lo_[1] < std::int64_t(size_[1]); ++j)
        for (std::int64_t k = std::max(first[2], lo_[2]); k <= last[2] && k - lo_[2] < std::int64_t(size_[2]); ++k) {
          const std::size_t index = ((i - lo_[0]) * size_[1] + (j - lo_[1])) * size_[2] + (k - lo_[2]);
          if (!occupied_[index]) continue;
          cells_[index * stride_ + 1] += static_cast<std::uint64_t>(mass * kVolumeMassUnit + 0.5);
          return;
        }
  }
  /// @brief True when the voxel at continuous voxel coordinates `u` is on the grid and in the
  /// job's box.
  bool in_box(const double* u) const {
    for (int a = 0; a < 3; ++a) {
      const double f = std::floor(u[a]);
      if (!(f >= 0.0 && f < grid_.dims[a])) return false;
      if (static_cast<std::uint64_t>(static_cast<std::int64_t>(f) - lo_[a]) >= size_[a]) return false;
    }
    return true;
  }
  /// @brief True when the voxel at continuous voxel coordinates `u` lies in the job's box and
  /// holds a point.
  bool occupied_voxel(const double* u) const {
    std::uint64_t d[3];
    for (int a = 0; a < 3; ++a) {
      const double f = std::floor(u[a]);
      if (!(f >= 0.0 && f < grid_.dims[a])) return false;
      d[a] = static_cast<std::uint64_t>(static_cast<std::int64_t>(f) - lo_[a]);
      if (d[a] >= size_[a]) return false;
    }
    return occupied_[(d[0] * size_[1] + d[1]) * size_[2] + d[2]] != 0;
  }
  /// @brief True when every voxel meeting the continuous voxel box [lo, hi] already holds a
  /// point of this job (false when one lies outside the job's box).
  bool occupied(const double* lo, const double* hi) const {
    std::int64_t first[3], last[3];
    for (int a = 0; a < 3; ++a) {
      first[a] = static_cast<std::int64_t>(std::floor(lo[a]));
      last[a] = static_cast<std::int64_t>(std::floor(hi[a]));
    }
    return occupied(first, last);
  }
  /// @brief The same for the voxels [first, last] (inclusive, per axis).
  bool occupied(const std::int64_t* first, const std::int64_t* last) const {
    std::int64_t from[3], count[3];
    for (int a = 0; a < 3; ++a) {
      from[a] = first[a] - lo_[a];
      count[a] = last[a] - first[a] + 1;
      if (from[a] < 0 || from[a] + count[a] > static_cast<std::int64_t>(size_[a])) return false;
    }
    const std::int64_t row = static_cast<std::int64_t>(size_[2]), slice = row * static_cast<std::int64_t>(size_[1]);
    const std::uint8_t* base = occupied_.data() + from[0] * slice + from[1] * row + from[2];
    for (std::int64_t i = 0; i < count[0]; ++i, base += slice) {
      const std::uint8_t* line = base;
      for (std::int64_t j = 0; j < count[1]; ++j, line += row)
        for (std::int64_t k = 0; k < count[2]; ++k)
          if (!line[k]) return false;
    }
    return true;
  }
  /// @brief The job's occupied voxels, sorted by key; the accumulator is ready for begin().
  VoxelList finish();

 private:
  const VoxelGrid& grid_;
  const ChannelQuantizer& quantizer_;
  double inverse_;
  int channels_, stride_;
  std::int64_t lo_[3] = {0, 0, 0};
  std::uint64_t size_[3] = {0, 0, 0};
  /// The box's cells, zero between jobs (finish() clears what it read): grown as fresh zero pages
  /// (huge pages from 1 MB), so that a cell's page is first touched by its first point.
  ZeroedVector<std::uint64_t> cells_;
  std::vector<std::uint64_t> values_;
  /// 1 where the cell holds a hit: the occupancy tests read these bytes, which stay in cache.
  ZeroedVector<std::uint8_t> occupied_;
  VoxelList overflow_;
};

}  // namespace ifsforge
