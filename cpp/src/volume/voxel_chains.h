#pragma once
/// @file The random-iteration volume's chain lanes (seed 5.1.1): up to 8 jobs' orbits side by
/// side in vector lanes, as the chaos game's chain lanes (render/chaos_chains.h) walk them (each
/// job's own xoshiro256+ stream and MapChain draws, the general path's operations in its order,
/// no fused multiply-add), each point's voxel found as VoxelGrid::voxel_of finds it and its
/// channels quantised as ChannelQuantizer::quantize does: every key and value is the one-job
/// loop's bit for bit. A batch of keys and values goes to the host (VoxelChains), which adds
/// them to its voxel table; the sums do not depend on the order of the adds. One kernel per
/// instruction set, each in its own translation unit (voxel_chains_avx2.cpp,
/// voxel_chains_avx512.cpp, one source for both: voxel_chains_kernel.h); like chaos_chains.h
/// this header holds plain data only.
#include <cstddef>
#include <cstdint>

#include "../render/chaos_chains.h"

namespace ifsforge::chains {

/// Points per batch handed to the host; a buffer holds kMaxChains more (a step's stores run past).
constexpr std::size_t kVoxelBatch = 64;
constexpr std::size_t kVoxelStride = kVoxelBatch + kMaxChains;
/// The key of a point off the grid (real keys have 63 bits).
constexpr std::uint64_t kOffGrid = ~std::uint64_t(0);
/// Bits per axis of a voxel key (VoxelGrid::kKeyBits: the host checks that they agree).
constexpr int kVoxelKeyBits = 21;

/// Up to kMaxChains jobs of a random-iteration volume and where their points go.
struct VoxelJob {
  /// The chains: starts, streams, maps, points per chain and skipped steps (its pixel fields unused).
  Job orbits;
  /// VoxelGrid's origin, voxel size and dimensions (as doubles: voxel_of's compares).
  double origin[3], voxel_size, dims[3];
  /// ChannelQuantizer's lower bounds and scales, and its steps.
  double lo[kMaxDim], scale[kMaxDim], steps;
  /// kVoxelStride keys, kOffGrid for points off the grid; channel c's levels at values + c * kVoxelStride.
  std::uint64_t* keys;
  std::uint64_t* values;
  /// Receives each batch of n points, chain 0's first in each step.
  void (*flush)(void* sink, const std::uint64_t* keys, const std::uint64_t* values, std::size_t n);
  void* sink;
};

/// Runs `job`; false when a point left the grid for good (its x + y + z no longer finite), as the
/// one-job loop's DivergentSystemError.
using VoxelKernel = bool (*)(const Maps&, const VoxelJob&);

bool run_voxels_avx2(const Maps&, const VoxelJob&);
bool run_voxels_avx512(const Maps&, const VoxelJob&);

}  // namespace ifsforge::chains
