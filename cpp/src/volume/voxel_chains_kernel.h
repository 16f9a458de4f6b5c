// The random-iteration volume's chain lanes (voxel_chains.h), written once for every vector
// width: a per-ISA unit includes its `V` (render/chaos_chains_avx2.h, chaos_chains_avx512.h),
// defines `Voxels` (each lane's voxel key and quantised levels, in that set's intrinsics), then
// includes this file, so that everything here is compiled for that set and has internal linkage.
// The orbits are the chaos game's (render/chaos_chains_orbits.h): the same draws, the same maps,
// the same bits.
#include <cmath>
#include <cstdint>

#include "../render/chaos_chains_orbits.h"
#include "voxel_chains.h"

namespace ifsforge::chains {
namespace {

/// Whether a point of a step that fell off the grid (key kOffGrid) has left for good: the
/// one-job loop's test, std::isfinite(x + y + z), lane by lane.
template <int N>
bool escaped(const Quad<N>& q, const std::uint64_t* keys) {
  alignas(sizeof(D)) double x[kLanes], y[kLanes], z[kLanes];
  V::store(reinterpret_cast<std::uint64_t*>(x), V::bits(q.p[0]));
  V::store(reinterpret_cast<std::uint64_t*>(y), V::bits(q.p[1]));
  V::store(reinterpret_cast<std::uint64_t*>(z), V::bits(q.p[2]));
  for (int k = 0; k < kLanes; ++k)
    if (keys[k] == kOffGrid && !std::isfinite(x[k] + y[k] + z[k])) return true;
  return false;
}

/// G registers of chains walk job.orbits.points steps after the skipped ones; each step's points
/// go to the batch as keys and levels, and each full batch to the host.
template <int N, int G, class Coefficients>
bool run_voxels(const Maps& m, const VoxelJob& job) {
  constexpr int kChannels = N - 3;
  const Job& orbits = job.orbits;
  const Coefficients coefficients(m);
  const I count = V::set1(static_cast<long long>(m.count));
  Quad<N> quads[G];
  start_quads(coefficients, m, orbits, count, quads);
  const Voxels voxels(job);
  D lo[kChannels + 1], scale[kChannels + 1];
  for (int c = 0; c < kChannels; ++c) {
    lo[c] = V::set1(job.lo[c]);
    scale[c] = V::set1(job.scale[c]);
  }
  const D zero = V::set1(0.0), steps = V::set1(job.steps), half = V::set1(0.5);
  std::size_t filled = 0;
  for (std::uint64_t i = 0; i < orbits.points; ++i) {
    for (int g = 0; g < G; ++g) {
      Quad<N>& q = quads[g];
      coefficients.apply(q);
      coefficients.choose(q, m, count);
      const std::size_t at = filled + g * kLanes;
      if (voxels.store_keys(job.keys + at, q.p) && escaped(q, job.keys + at)) return false;
      // ChannelQuantizer::quantize: q < 0 ? 0 : min(q, steps) is max(q, 0) then the min (a zero
      // of either sign gives level 0 both ways), plus a half, truncated (below 2^31).
      for (int c = 0; c < kChannels; ++c) {
        const D scaled = V::mul(V::sub(q.p[3 + c], lo[c]), scale[c]);
        voxels.store_level(job.values + c * kVoxelStride + at, V::add(V::min(V::max(scaled, zero), steps), half));
      }
    }
    if ((filled += orbits.chains) + kMaxChains > kVoxelBatch) {
      job.flush(job.sink, job.keys, job.values, filled);
      filled = 0;
    }
  }
  if (filled) job.flush(job.sink, job.keys, job.values, filled);
  return true;
}

template <int N, class Coefficients>
bool run_voxel_groups(const Maps& m, const VoxelJob& job) {
  if constexpr (kGroups > 1)
    if (job.orbits.chains > kLanes) return run_voxels<N, kGroups, Coefficients>(m, job);
  return run_voxels<N, 1, Coefficients>(m, job);
}

/// The maps' shape: a volume's three spatial coordinates, diagonal (similitudes without rotation,
/// 3D) or blocked (channels), else dense.
template <int N, template <int, Shape> class Kind>
bool run_voxel_shapes(const Maps& m, const VoxelJob& job) {
  if constexpr (N == 3)
    if (m.diagonal) return run_voxel_groups<N, Kind<N, kDiagonal>>(m, job);
  if constexpr (N >= 4)
    if (m.blocked) return run_voxel_groups<N, Kind<N, kBlocked3>>(m, job);
  return run_voxel_groups<N, Kind<N, kDense>>(m, job);
}

/// The draw's kind as the chaos game's kernel picks it (chaos_chains_kernel.h's run_dim).
template <int N>
bool run_voxel_dim(const Maps& m, const VoxelJob& job) {
  if constexpr (N == 3)
    if (m.direct && m.draws) return run_voxel_shapes<N, SharedLinearOffsets>(m, job);
  if (m.draws) return run_voxel_shapes<N, SharedLinearDraws>(m, job);
  if (m.count <= kLanes)
    return m.shared_linear ? run_voxel_shapes<N, SharedLinear>(m, job) : run_voxel_shapes<N, FewCoefficients>(m, job);
  return run_voxel_shapes<N, ManyCoefficients>(m, job);
}

/// This unit's kernel for a volume's dimensions (3 to 8).
bool run_voxel_lanes(const Maps& m, const VoxelJob& job) {
  using Run = bool (*)(const Maps&, const VoxelJob&);
  static constexpr Run kRuns[] = {run_voxel_dim<3>, run_voxel_dim<4>, run_voxel_dim<5>,
                                  run_voxel_dim<6>, run_voxel_dim<7>, run_voxel_dim<8>};
  return kRuns[m.dim - 3](m, job);
}

}  // namespace
}  // namespace ifsforge::chains
