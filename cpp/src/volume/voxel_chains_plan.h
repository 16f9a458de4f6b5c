#pragma once
// The host side of the random-iteration volume's chain lanes (voxel_chains.h): the system's
// tables (the chaos game's, render/chaos_chains_plan.h), the jobs' streams, the kernel for this
// CPU, and each batch of points added to a worker's voxel table. Private to the volume renderers.
#include <cstdint>

#include "../render/chaos_chains_plan.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/volume/voxel_grid.h"
#include "ifsforge/volume/voxel_list.h"
#include "voxel_chains.h"
#include "voxel_table.h"

namespace ifsforge {

class VoxelChains {
 public:
  /// The lanes of the instruction set the chaos game's kernels take now (IFSFORGE_ISA and the
  /// CPU: chaos_lanes.h's lane_isa); none on baseline x86-64, where the one-job loop runs.
  VoxelChains(const Ifs& ifs, const MapChain& chain, const VoxelGrid& grid, const ChannelQuantizer& quantizer);
  VoxelChains(const VoxelChains&) = delete;  // the job points into the tables
  VoxelChains& operator=(const VoxelChains&) = delete;

  bool available() const { return kernel_ != nullptr; }

  /// @brief Jobs [first, first + count) (count at most chains::kMaxChains), each `points` points
  /// after `skip` unplotted ones from its own stream (seed, job), exactly as the one-job loop
  /// draws them, added to `table` batch by batch. DivergentSystemError when a point escapes to
  /// infinity.
  void run(std::uint64_t first, int count, std::uint64_t points, std::uint64_t skip, std::uint64_t seed,
           VoxelTable& table) const;

 private:
  const Ifs& ifs_;
  const MapChain& chain_;
  chains::MapTables tables_;
  chains::VoxelKernel kernel_;
  chains::VoxelJob grid_{};  ///< the grid's and the quantiser's fields of every job
};

}  // namespace ifsforge
