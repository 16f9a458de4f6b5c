// The chain lanes' kernel (chaos_chains.h), written once for every vector width: a per-ISA unit
// (chaos_chains_avx2.cpp: 4 doubles per register; chaos_chains_avx512.cpp: 8) includes its `V`
// (chaos_chains_avx2.h, chaos_chains_avx512.h: registers and plain intrinsics, each the same IEEE
// operation on every lane), then this file (the orbits: chaos_chains_orbits.h), so that
// everything here is compiled for that unit's instruction set and has internal linkage. Each lane
// performs the baseline kernel's operations in its order: separate multiplies and adds (the units
// are compiled with -ffp-contract=off like the whole library), so the bits are the same whatever
// the width.
#include <immintrin.h>

#include <cstdint>
#include <type_traits>

#include "chaos_chains_orbits.h"

namespace ifsforge::chains {
namespace {

/// A batch into Job::records (kRecords): each point's record word, V::store_records's (its hit
/// and its three levels), added to its pixel's record at once (V::add_record); a sum below its
/// level wrapped, as in ChannelSink::add_levels.
struct ToRecords {
  static void add(const Job& job, const std::uint32_t* slots, const std::uint32_t* words, const float*, std::size_t n) {
    std::uint32_t* const records = job.records;  // read once: the records' stores may alias job
    std::uint64_t* const carry = job.carry;
#pragma GCC unroll 4
    for (std::size_t i = 0; i < n; ++i) {  // unrolled: the loop's own count and branch were a quarter of its work
      const std::size_t pixel = slots[i];
      if (const int wrapped = V::add_record(records + pixel * 4, words + 4 * i))
        for (int c = 0; c < 3; ++c)
          if (wrapped >> (1 + c) & 1) __atomic_fetch_add(carry + pixel * 3 + c, std::uint64_t(1) << 32, __ATOMIC_RELAXED);
    }
  }
};

/// kRecords: a 2D system of three channels whose points go to Job::records (N is 5): the
/// channels' count known here, each step stores its points' record words, and the kernel adds
/// them (ToRecords) where the sink would have (no call, and no transposes of levels there).
template <int N, int G, class Coefficients, bool kRecords>
void run(const Maps& m, const Job& job) {
  constexpr int kTerms = N < 3 ? N : 3;
  const Coefficients coefficients(m);
  const I count = V::set1(static_cast<long long>(m.count));
  Quad<N> quads[G];
  start_quads(coefficients, m, job, count, quads);
  const D zero = V::set1(0.0);
  const V::Screen screen(m);
  const int channels = m.dim - m.spatial;
  D lo[kMaxDim], scale[kMaxDim];
  for (int c = 0; c < channels; ++c) {
    lo[c] = V::set1(m.lo[c]);
    scale[c] = V::set1(m.scale[c]);
  }
  const D steps = V::set1(m.steps), half = V::set1(0.5);
  Batches<std::conditional_t<kRecords, ToRecords, ToSink>> batches(job, channels);
  const std::uint32_t* ahead[G] = {};  // each group's slots of the step before, to prefetch
  for (std::uint64_t i = 0; i < job.points; ++i) {
    std::uint32_t* slots = batches.slots();
    std::uint32_t* levels = batches.levels();
    float* depths = batches.depths();
    const std::size_t filled = batches.filled();
    for (int g = 0; g < G; ++g) {
      Quad<N>& q = quads[g];
      coefficients.apply(q);
      coefficients.choose(q, m, count);
      D px = V::set1(m.u0), py = V::set1(m.v0);
      if (m.planar) {
        px = V::add(px, V::mul(V::set1(m.u[0]), q.p[0]));
        py = V::add(py, V::mul(V::set1(m.v[1]), q.p[1]));
      } else {
        for (int t = 0; t < kTerms; ++t) {
          px = V::add(px, V::mul(V::set1(m.u[t]), q.p[t]));
          py = V::add(py, V::mul(V::set1(m.v[t]), q.p[t]));
        }
      }
      const std::size_t at = filled + g * kLanes;
      screen.store(slots + at, px, py);
      // The slots of the group's step before, read back from its batch (loads and scalar
      // arithmetic, beside the vector work: the addresses computed in registers and extracted
      // took as long). Not this step's, whose loads of the lanes just stored held up the step
      // (perf put a quarter of the colour fern's samples on them; the fern's point cost 8% less
      // with the step before's), and the batch reaches the counters a batch later either way.
      if (const std::uint32_t* before = ahead[g]) {
        if constexpr (kRecords) {
          for (int k = 0; k < kLanes; ++k) _mm_prefetch(reinterpret_cast<const char*>(job.records + std::size_t(before[k]) * 4), _MM_HINT_T0);
        } else {
          for (int k = 0; k < kLanes; ++k) _mm_prefetch(job.counters + before[k] * job.counter_bytes, _MM_HINT_T0);
        }
      }
      ahead[g] = slots + at;
      // Accumulator::quantised: q < 0 ? 0 : min(q, steps) is max(q, 0) then the min (a zero of
      // either sign gives level 0 both ways), and the levels are below 2^31: truncation to 32 bits
      // is the conversion to 64.
      auto level = [&](int c, int at_c) {
        const D scaled = V::mul(V::sub(q.p[at_c], lo[c]), scale[c]);
        return V::add(V::min(V::max(scaled, zero), steps), half);
      };
      if constexpr (kRecords) {
        V::store_records(levels + 4 * at, level(0, 2), level(1, 3), level(2, 4));
      } else {
        for (int c = 0; c < channels; ++c) V::store_truncated(levels + c * kStride + at, level(c, m.spatial + c));
      }
      if constexpr (N >= 3 && !kRecords)
        if (m.spatial == 3) {  // rounded to float as Accumulator::add_depth
          const D depth = V::add(V::add(V::mul(V::set1(m.toward[0]), q.p[0]), V::mul(V::set1(m.toward[1]), q.p[1])),
                                 V::mul(V::set1(m.toward[2]), q.p[2]));
          V::store_rounded(depths + at, depth);
        }
    }
    batches.advance(job.chains);
  }
  batches.finish();
}

template <int N, class Coefficients, bool kRecords>
void run_groups(const Maps& m, const Job& job) {
  if constexpr (kGroups > 1)
    if (job.chains > kLanes) return run<N, kGroups, Coefficients, kRecords>(m, job);
  run<N, 1, Coefficients, kRecords>(m, job);
}

template <int N, class Coefficients>
void run_with(const Maps& m, const Job& job) {
  if constexpr (N == 5)
    if (job.records) return run_groups<N, Coefficients, true>(m, job);
  run_groups<N, Coefficients, false>(m, job);
}

/// The kernel for the maps' linear parts' shape: diagonal (similitudes without rotation, in 2D
/// and 3D), blocked (a colour system's channels; by height where they take no x), or dense.
template <int N, template <int, Shape> class Kind>
void run_shaped(const Maps& m, const Job& job) {
  if constexpr (N <= 3)
    if (m.diagonal) return run_with<N, Kind<N, kDiagonal>>(m, job);
  // By height only with three channels (2D colour, whose records the kernel adds itself: the
  // HSI fern's channels take y, seed 6.4.3): other widths take kBlocked2, the same bits.
  if constexpr (N == 5)
    if (m.by_height && m.spatial == 2) return run_with<N, Kind<N, kHeight2>>(m, job);
  if constexpr (N >= 3)
    if (m.blocked && m.spatial == 2) return run_with<N, Kind<N, kBlocked2>>(m, job);
  if constexpr (N >= 4)
    if (m.blocked && m.spatial == 3) return run_with<N, Kind<N, kBlocked3>>(m, job);
  run_with<N, Kind<N, kDense>>(m, job);
}

template <int N>
void run_dim(const Maps& m, const Job& job) {
  if constexpr (N <= 3)
    if (m.direct && m.draws) return run_shaped<N, SharedLinearOffsets>(m, job);
  if (m.draws)
    run_shaped<N, SharedLinearDraws>(m, job);
  else if (m.count <= kLanes)
    m.shared_linear ? run_shaped<N, SharedLinear>(m, job) : run_shaped<N, FewCoefficients>(m, job);
  else
    run_shaped<N, ManyCoefficients>(m, job);
}

/// This unit's kernel for any dimension.
void run_lanes(const Maps& m, const Job& job) {
  using Run = void (*)(const Maps&, const Job&);
  static constexpr Run kRuns[] = {run_dim<2>, run_dim<3>, run_dim<4>, run_dim<5>, run_dim<6>, run_dim<7>, run_dim<8>};
  kRuns[m.dim - 2](m, job);
}

}  // namespace
}  // namespace ifsforge::chains
