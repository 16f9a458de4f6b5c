#include "ifsforge/volume/voxel_accumulator.h"

#include <algorithm>

namespace ifsforge {

VoxelAccumulator::VoxelAccumulator(const VoxelGrid& grid, const ChannelQuantizer& quantizer)
    : grid_(grid), quantizer_(quantizer), inverse_(1.0 / grid.voxel_size), channels_(quantizer.channels()),
      stride_(2 + quantizer.channels()), values_(quantizer.channels()), overflow_(quantizer.channels()) {}

void VoxelAccumulator::begin(const double* lo, const double* hi) {
  std::size_t cells = 1;
  for (int a = 0; a < 3; ++a) {
    // One voxel of slack: points of the piece may sit just outside its box's image.
    const double first = std::clamp(std::floor(lo[a]) - 1.0, 0.0, grid_.dims[a] - 1.0);
    const double last = std::clamp(std::floor(hi[a]) + 1.0, 0.0, grid_.dims[a] - 1.0);
    lo_[a] = static_cast<std::int64_t>(first);
    size_[a] = last >= first ? static_cast<std::uint64_t>(last - first) + 1 : 0;
    cells *= size_[a];
  }
  if (cells > kMaxBoxCells) {
    size_[0] = size_[1] = size_[2] = 0;
    cells = 0;
  }
  // Larger storage replaces the old without copying it: both are all zeros here.
  if (cells_.size() < cells * stride_) ZeroedVector<std::uint64_t>(cells * stride_).swap(cells_);
  if (occupied_.size() < cells) ZeroedVector<std::uint8_t>(cells).swap(occupied_);
}

VoxelList VoxelAccumulator::finish() {
  VoxelList list(channels_);
  std::size_t occupied = overflow_.size();
  for (std::size_t cell = 0; cell < size_[0] * size_[1] * size_[2]; ++cell) occupied += occupied_[cell];
  list.reserve(occupied);
  std::size_t cell = 0;
  for (std::uint64_t i = 0; i < size_[0]; ++i)
    for (std::uint64_t j = 0; j < size_[1]; ++j)
      for (std::uint64_t k = 0; k < size_[2]; ++k, ++cell) {
        std::uint64_t* c = &cells_[cell * stride_];
        if (!occupied_[cell]) continue;
        occupied_[cell] = 0;
        list.push(VoxelGrid::key(lo_[0] + i, lo_[1] + j, lo_[2] + k), c[0], c[1], c + 2);
        std::fill_n(c, stride_, 0);
      }
  if (overflow_.size()) {
    for (std::size_t e = 0; e < overflow_.size(); ++e) list.push_from(overflow_, e);
    sort_and_reduce(list);
    overflow_ = VoxelList(channels_);
  }
  return list;
}

}  // namespace ifsforge
