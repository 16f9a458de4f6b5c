#include "voxel_chains_plan.h"

#include <cstring>
#include <vector>

#include "../render/chaos_lanes.h"
#include "ifsforge/core/error.h"

namespace ifsforge {
namespace {

static_assert(chains::kVoxelKeyBits == VoxelGrid::kKeyBits, "the lanes pack keys as VoxelGrid::key does");

/// Where a batch goes: each point on the grid added to `table`, every slot of the batch
/// prefetched first. Not through VoxelBins, as the one-job loop adds into a large table: with
/// the lanes' points the bins cost more than they saved (the tetrahedron at 1024³, 5e7 points, one
/// thread, a fresh process: 5.5-6.2 CPU s through bins asked at each growth of the table,
/// 3.1-3.3 s added directly, the one-job loop 3.4-4.1 s), for reasons not yet understood.
template <int Channels>
void add_batch(void* sink, const std::uint64_t* keys, const std::uint64_t* values, std::size_t n) {
  VoxelTable& table = *static_cast<VoxelTable*>(sink);
  for (std::size_t i = 0; i < n; ++i)
    if (keys[i] != chains::kOffGrid) table.prefetch(keys[i]);
  std::uint64_t point[Channels + 1];
  for (std::size_t i = 0; i < n; ++i) {
    if (keys[i] == chains::kOffGrid) continue;
    for (int c = 0; c < Channels; ++c) point[c] = values[c * chains::kVoxelStride + i];
    table.add_hit<Channels>(keys[i], point);
  }
}

}  // namespace

VoxelChains::VoxelChains(const Ifs& ifs, const MapChain& chain, const VoxelGrid& grid,
                         const ChannelQuantizer& quantizer)
    : ifs_(ifs), chain_(chain), tables_(ifs, chain) {
  const char* isa = lanes::lane_isa();
  kernel_ = std::strcmp(isa, "avx512") == 0 ? chains::run_voxels_avx512
            : std::strcmp(isa, "avx2") == 0 ? chains::run_voxels_avx2
                                            : nullptr;
  for (int a = 0; a < 3; ++a) {
    grid_.origin[a] = grid.origin[a];
    grid_.dims[a] = grid.dims[a];
  }
  grid_.voxel_size = grid.voxel_size;
  for (int c = 0; c < quantizer.channels(); ++c) {
    grid_.lo[c] = quantizer.lo()[c];
    grid_.scale[c] = quantizer.scale()[c];
  }
  grid_.steps = ChannelQuantizer::kSteps;
}

void VoxelChains::run(std::uint64_t first, int count, std::uint64_t points, std::uint64_t skip, std::uint64_t seed,
                      VoxelTable& table) const {
  chains::VoxelJob job = grid_;
  job.orbits = chains::start_chains(ifs_, chain_, seed, first, count, points, skip);
  const int channels = ifs_.dim() - 3;
  std::vector<std::uint64_t> keys(chains::kVoxelStride), values(channels * chains::kVoxelStride + 1);
  job.keys = keys.data();
  job.values = values.data();
  using Add = void (*)(void*, const std::uint64_t*, const std::uint64_t*, std::size_t);
  static constexpr Add kAdds[] = {add_batch<0>, add_batch<1>, add_batch<2>, add_batch<3>, add_batch<4>, add_batch<5>};
  job.flush = kAdds[channels];
  job.sink = &table;
  if (!kernel_(tables_.maps(), job))
    throw DivergentSystemError("system '" + ifs_.name() + "' escapes to infinity under iteration");
}

}  // namespace ifsforge
