#pragma once
// The chain lanes' registers and operations for AVX2 (four doubles per register;
// units compiled with -mavx2 -mfma):
// `V`, in the anonymous namespace of ifsforge::chains, for chaos_chains_orbits.h and the kernels
// that include it (chaos_chains_avx2.cpp, volume/voxel_chains_avx2.cpp). Include it only where
// the unit's instruction set has them.
#include "chaos_chains.h"

#include <immintrin.h>

namespace ifsforge::chains {
namespace {

/// Four doubles or 64-bit integers per register.
struct V {
  static constexpr int kLanes = 4;
  using D = __m256d;
  using I = __m256i;
  using Keep = __m256i;   ///< per lane all ones where the draw keeps its column
  using Index = __m256i;  ///< a permute's index of 32-bit halves (index)

  static D set1(double x) { return _mm256_set1_pd(x); }
  static I set1(long long x) { return _mm256_set1_epi64x(x); }
  static D load(const double* from) { return _mm256_load_pd(from); }
  static I load(const std::uint64_t* from) { return _mm256_load_si256(reinterpret_cast<const __m256i*>(from)); }
  static void store(std::uint64_t* to, I x) { _mm256_store_si256(reinterpret_cast<__m256i*>(to), x); }
  static D add(D a, D b) { return _mm256_add_pd(a, b); }
  static D sub(D a, D b) { return _mm256_sub_pd(a, b); }
  static D mul(D a, D b) { return _mm256_mul_pd(a, b); }
  static D min(D a, D b) { return _mm256_min_pd(a, b); }
  static D max(D a, D b) { return _mm256_max_pd(a, b); }
  static I add(I a, I b) { return _mm256_add_epi64(a, b); }
  static I bit_xor(I a, I b) { return _mm256_xor_si256(a, b); }
  /// The low 32 bits of each lane's a times those of b, 64 bits wide.
  static I mul_low(I a, I b) { return _mm256_mul_epu32(a, b); }
  template <int k>
  static I shift_left(I x) { return _mm256_slli_epi64(x, k); }
  template <int k>
  static I shift_right(I x) { return _mm256_srli_epi64(x, k); }
  template <int k>
  static I rotate_left(I x) { return _mm256_or_si256(_mm256_slli_epi64(x, k), _mm256_srli_epi64(x, 64 - k)); }
  static I bits(D x) { return _mm256_castpd_si256(x); }
  static D doubles(I x) { return _mm256_castsi256_pd(x); }

  /// The permute that takes map i's double (floats 2i and 2i + 1 of a table) into each lane.
  static Index index(I map) {
    const __m256i twice = _mm256_slli_epi64(map, 1);
    return _mm256_or_si256(twice, _mm256_slli_epi64(_mm256_add_epi64(twice, _mm256_set1_epi64x(1)), 32));
  }
  /// Each lane's map's double of a table that holds map i's in lane i.
  static D lookup(D table, Index index) {
    return _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(table), index));
  }
  static I gather(const std::uint64_t* from, I at) {
    return _mm256_i64gather_epi64(reinterpret_cast<const long long*>(from), at, 8);
  }

  /// Whether each lane's threshold (the choice's low 32 bits) exceeds the random number's low 32
  /// bits: both below 2^32, the signed 64-bit compare is the unsigned 32-bit one.
  static Keep keeps(I choice, I random) {
    const __m256i low32 = _mm256_set1_epi64x(0xFFFFFFFFll);
    return _mm256_cmpgt_epi64(_mm256_and_si256(choice, low32), _mm256_and_si256(random, low32));
  }
  static I select(Keep keep, I yes, I no) { return _mm256_blendv_epi8(no, yes, keep); }
  static D select(Keep keep, D yes, D no) { return _mm256_blendv_pd(no, yes, _mm256_castsi256_pd(keep)); }

  /// Coefficients k to k + 3 of each lane's row (lane i's at from[at[i]]), a register per
  /// coefficient: four loads and a 4x4 transpose (loads and shuffles cost less than gathers).
  static void rows(const double* from, const std::uint64_t* at, D* out) {
    const __m256d r0 = _mm256_loadu_pd(from + at[0]), r1 = _mm256_loadu_pd(from + at[1]);
    const __m256d r2 = _mm256_loadu_pd(from + at[2]), r3 = _mm256_loadu_pd(from + at[3]);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    out[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
    out[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
    out[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
    out[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
  }
  /// Rows of two doubles (2D offsets): the first of each lane's into x, the second into y. Lanes
  /// 0 and 2, 1 and 3 side by side: their low and high halves are x's and y's.
  static void pairs(const double* from, const std::uint64_t* at, D& x, D& y) {
    const __m256d even = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(from + at[0])),
                                              _mm_loadu_pd(from + at[2]), 1);
    const __m256d odd = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(from + at[1])),
                                             _mm_loadu_pd(from + at[3]), 1);
    x = _mm256_unpacklo_pd(even, odd);
    y = _mm256_unpackhi_pd(even, odd);
  }

  /// Levels below 2^31, truncated to 32 bits.
  static void store_truncated(std::uint32_t* to, D x) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(to), _mm256_cvttpd_epi32(x));
  }
  static void store_rounded(float* to, D x) { _mm_storeu_ps(to, _mm256_cvtpd_ps(x)); }
  /// Each lane's record word: 1 (its hit), then its three levels (below 2^31) truncated to 32
  /// bits, lane k's at to + 4 k: the four lanes' (1, l0, l1, l2) transposed.
  static void store_records(std::uint32_t* to, D level0, D level1, D level2) {
    const __m128i one = _mm_set1_epi32(1), l0 = _mm256_cvttpd_epi32(level0);
    const __m128i l1 = _mm256_cvttpd_epi32(level1), l2 = _mm256_cvttpd_epi32(level2);
    const __m128i low01 = _mm_unpacklo_epi32(one, l0), low23 = _mm_unpacklo_epi32(l1, l2);
    const __m128i high01 = _mm_unpackhi_epi32(one, l0), high23 = _mm_unpackhi_epi32(l1, l2);
    __m128i* words = reinterpret_cast<__m128i*>(to);
    _mm_storeu_si128(words, _mm_unpacklo_epi64(low01, low23));
    _mm_storeu_si128(words + 1, _mm_unpackhi_epi64(low01, low23));
    _mm_storeu_si128(words + 2, _mm_unpacklo_epi64(high01, high23));
    _mm_storeu_si128(words + 3, _mm_unpackhi_epi64(high01, high23));
  }
  /// A record word added to a pixel's record (four 32-bit sums); bit 1 + c set where channel c's
  /// sum wrapped (came out below what it took, where the unsigned maximum of both is not the sum;
  /// the hits, flushed first, never do).
  static int add_record(std::uint32_t* record, const std::uint32_t* word) {
    const __m128i w = _mm_loadu_si128(reinterpret_cast<const __m128i*>(word));
    const __m128i sum = _mm_add_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(record)), w);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(record), sum);
    const int kept = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(_mm_max_epu32(sum, w), sum)));
    return (kept ^ 0xF) & 0xE;
  }

  /// The frame's pixels: each lane's slot, the trash one off the image.
  struct Screen {
    __m256d zero, width, height;
    __m128i columns, trash;
    __m256i low_halves;

    explicit Screen(const Maps& m)
        : zero(_mm256_setzero_pd()),
          width(_mm256_set1_pd(m.width)),
          height(_mm256_set1_pd(m.height)),
          columns(_mm_set1_epi32(static_cast<int>(m.columns))),
          trash(_mm_set1_epi32(static_cast<int>(m.trash))),
          low_halves(_mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6)) {}

    void store(std::uint32_t* to, D px, D py) const {
      // Ordered compares: a NaN is outside, as in the general path.
      const __m256d inside = _mm256_and_pd(
          _mm256_and_pd(_mm256_cmp_pd(px, zero, _CMP_GE_OQ), _mm256_cmp_pd(px, width, _CMP_LT_OQ)),
          _mm256_and_pd(_mm256_cmp_pd(py, zero, _CMP_GE_OQ), _mm256_cmp_pd(py, height, _CMP_LT_OQ)));
      const __m128i in32 =
          _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(inside), low_halves));
      // Inside, both are in [0, 2^31): truncation is the general path's size_t conversion.
      const __m128i slot =
          _mm_add_epi32(_mm_mullo_epi32(_mm256_cvttpd_epi32(py), columns), _mm256_cvttpd_epi32(px));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(to), _mm_blendv_epi8(trash, slot, in32));
    }
  };
};

}  // namespace
}  // namespace ifsforge::chains
