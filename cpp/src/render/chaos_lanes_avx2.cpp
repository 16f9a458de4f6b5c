// The lane kernel for AVX2 + FMA (compiled with -mavx2 -mfma whatever the library's flags; run
// only where the CPU has both, see lane_kernel). It includes nothing of the library but
// chaos_lanes.h, and its helpers have internal linkage: nothing compiled here can stand in for
// a baseline function.
#include "chaos_lanes.h"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>

namespace ifsforge::lanes {
namespace {

template <int N>
struct Registers {
  __m256 a[N * N], b[N];
  __m256i thresholds[7];
  int count;

  explicit Registers(const Maps& m) : count(m.count) {
    for (int k = 0; k < N * N; ++k) a[k] = _mm256_load_ps(m.a[k]);
    for (int r = 0; r < N; ++r) b[r] = _mm256_load_ps(m.b[r]);
    for (int j = 0; j + 1 < count; ++j) thresholds[j] = _mm256_set1_epi32(m.thresholds[j]);
  }
};

/// Eight chaos games at once in pixel space; xoshiro128+ per lane.
template <int N>
struct Lanes {
  __m256 p[N];
  __m256i s0, s1, s2, s3;

  __m256i next() {
    const __m256i result = _mm256_add_epi32(s0, s3);
    const __m256i t = _mm256_slli_epi32(s1, 9);
    s2 = _mm256_xor_si256(s2, s0);
    s3 = _mm256_xor_si256(s3, s1);
    s1 = _mm256_xor_si256(s1, s2);
    s0 = _mm256_xor_si256(s0, s3);
    s2 = _mm256_xor_si256(s2, t);
    s3 = _mm256_or_si256(_mm256_slli_epi32(s3, 11), _mm256_srli_epi32(s3, 21));
    return result;
  }

  void step(const Registers<N>& m) {
    const __m256i u = _mm256_srli_epi32(next(), 8);  // top 24 bits
    __m256i index = _mm256_setzero_si256();
    for (int j = 0; j + 1 < m.count; ++j) index = _mm256_sub_epi32(index, _mm256_cmpgt_epi32(u, m.thresholds[j]));
    __m256 q[N];
    for (int r = 0; r < N; ++r) {
      // Innermost term last: x' = a00 x + (a01 y + (... + b0)).
      __m256 value = _mm256_permutevar8x32_ps(m.b[r], index);
      for (int c = N - 1; c >= 0; --c)
        value = _mm256_fmadd_ps(_mm256_permutevar8x32_ps(m.a[r * N + c], index), p[c], value);
      q[r] = value;
    }
    for (int r = 0; r < N; ++r) p[r] = q[r];
  }

  /// Histogram slots of the eight points (the trash slot for points off the image).
  __m256i slots(__m256i width, __m256i height, __m256i trash) const {
    const __m256i ix = _mm256_cvttps_epi32(_mm256_floor_ps(p[0]));
    const __m256i iy = _mm256_cvttps_epi32(_mm256_floor_ps(p[1]));
    const __m256i minus1 = _mm256_set1_epi32(-1);
    const __m256i inside =
        _mm256_and_si256(_mm256_and_si256(_mm256_cmpgt_epi32(ix, minus1), _mm256_cmpgt_epi32(width, ix)),
                         _mm256_and_si256(_mm256_cmpgt_epi32(iy, minus1), _mm256_cmpgt_epi32(height, iy)));
    const __m256i slot = _mm256_add_epi32(_mm256_mullo_epi32(iy, width), ix);
    return _mm256_blendv_epi8(trash, slot, inside);
  }
};

/// 8-bit hits into `low` (2D), each wrap of a byte adding 256 to the shared wide totals (or the
/// slots in batches to job.flush), or hits and the largest depth per pixel (3D). The bytes keep a 1024^2 raster's counters inside the
/// core's cache; a wrap comes once in 256 hits of a pixel, so its atomic add (exact in any
/// order) costs little.
template <int N>
void run(const Maps& maps, const Job& job) {
  const Registers<N> m(maps);
  Lanes<N> lanes[kGroups];
  for (int g = 0; g < kGroups; ++g) {
    for (int c = 0; c < N; ++c) lanes[g].p[c] = _mm256_set1_ps(job.origin[c]);
    lanes[g].s0 = _mm256_load_si256(reinterpret_cast<const __m256i*>(job.state[g][0]));
    lanes[g].s1 = _mm256_load_si256(reinterpret_cast<const __m256i*>(job.state[g][1]));
    lanes[g].s2 = _mm256_load_si256(reinterpret_cast<const __m256i*>(job.state[g][2]));
    lanes[g].s3 = _mm256_load_si256(reinterpret_cast<const __m256i*>(job.state[g][3]));
  }
  for (std::uint64_t i = 0; i < job.skip; ++i)
    for (auto& l : lanes) l.step(m);
  const __m256i width = _mm256_set1_epi32(job.width);
  const __m256i height = _mm256_set1_epi32(job.height);
  const __m256i trash = _mm256_set1_epi32(job.width * job.height);
  alignas(32) std::uint32_t slot[kGroups][kWidth];
  alignas(32) float depth[kGroups][kWidth];
  std::size_t filled = 0;  // slots in job.batch
  for (std::uint64_t i = 0; i < job.points / kLanes; ++i) {
    if (N == 2 && job.batch) {
      for (int g = 0; g < kGroups; ++g) {
        lanes[g].step(m);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(job.batch + filled + g * kWidth),
                            lanes[g].slots(width, height, trash));
      }
      if ((filled += kLanes) == job.batch_size) {
        job.flush(job.sink, job.batch, filled);
        filled = 0;
      }
      continue;
    }
    for (int g = 0; g < kGroups; ++g) {
      lanes[g].step(m);
      _mm256_store_si256(reinterpret_cast<__m256i*>(slot[g]), lanes[g].slots(width, height, trash));
      if constexpr (N == 3) _mm256_store_ps(depth[g], lanes[g].p[2]);
    }
    for (int g = 0; g < kGroups; ++g)
      for (int k = 0; k < kWidth; ++k) {
        if constexpr (N == 3) {
          HitDepth& cell = job.cells[slot[g][k]];
          ++cell.hits;
          if (depth[g][k] > cell.depth) cell.depth = depth[g][k];
        } else {
          const std::uint32_t s = slot[g][k];
          if (++job.low[s] == 0) __atomic_fetch_add(job.carry + s, 256, __ATOMIC_RELAXED);
        }
      }
  }
  if (filled) job.flush(job.sink, job.batch, filled);
}

}  // namespace

void run_avx2_2(const Maps& maps, const Job& job) { run<2>(maps, job); }
void run_avx2_3(const Maps& maps, const Job& job) { run<3>(maps, job); }

}  // namespace ifsforge::lanes

#else  // not x86-64: lane_kernel never picks these

namespace ifsforge::lanes {
void run_avx2_2(const Maps& maps, const Job& job) { run_baseline2(maps, job); }
void run_avx2_3(const Maps& maps, const Job& job) { run_baseline3(maps, job); }
}  // namespace ifsforge::lanes

#endif
