#pragma once
// The chain lanes' registers and operations for AVX-512 (eight doubles per
// register; units compiled with -mavx512f -mavx512vl):
// `V`, in the anonymous namespace of ifsforge::chains, for chaos_chains_orbits.h and the kernels
// that include it (chaos_chains_avx512.cpp, volume/voxel_chains_avx512.cpp). Include it only where
// the unit's instruction set has them.
#include "chaos_chains.h"

#if defined(__GNUC__) && !defined(__clang__)
// GCC 12's AVX-512 headers start some intrinsics from an undefined register (`__m512i __Y =
// __Y`), which its own uninitialised-use warnings then report at every call (GCC bug 105593).
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <immintrin.h>

namespace ifsforge::chains {
namespace {

/// Eight doubles or 64-bit integers per register; a compare gives a mask register.
struct V {
  static constexpr int kLanes = 8;
  using D = __m512d;
  using I = __m512i;
  using Keep = __mmask8;  ///< per lane set where the draw keeps its column
  using Index = __m512i;  ///< a permute's index: the map itself

  static D set1(double x) { return _mm512_set1_pd(x); }
  static I set1(long long x) { return _mm512_set1_epi64(x); }
  static D load(const double* from) { return _mm512_load_pd(from); }
  static I load(const std::uint64_t* from) { return _mm512_load_si512(from); }
  static void store(std::uint64_t* to, I x) { _mm512_store_si512(to, x); }
  static D add(D a, D b) { return _mm512_add_pd(a, b); }
  static D sub(D a, D b) { return _mm512_sub_pd(a, b); }
  static D mul(D a, D b) { return _mm512_mul_pd(a, b); }
  static D min(D a, D b) { return _mm512_min_pd(a, b); }
  static D max(D a, D b) { return _mm512_max_pd(a, b); }
  static I add(I a, I b) { return _mm512_add_epi64(a, b); }
  static I bit_xor(I a, I b) { return _mm512_xor_si512(a, b); }
  /// The low 32 bits of each lane's a times those of b, 64 bits wide.
  static I mul_low(I a, I b) { return _mm512_mul_epu32(a, b); }
  template <int k>
  static I shift_left(I x) { return _mm512_slli_epi64(x, k); }
  template <int k>
  static I shift_right(I x) { return _mm512_srli_epi64(x, k); }
  template <int k>
  static I rotate_left(I x) { return _mm512_rol_epi64(x, k); }
  static I bits(D x) { return _mm512_castpd_si512(x); }
  static D doubles(I x) { return _mm512_castsi512_pd(x); }

  static Index index(I map) { return map; }
  /// Each lane's map's double of a table that holds map i's in lane i.
  static D lookup(D table, Index index) { return _mm512_permutexvar_pd(index, table); }
  static I gather(const std::uint64_t* from, I at) { return _mm512_i64gather_epi64(at, from, 8); }

  /// Whether each lane's threshold (the choice's low 32 bits) exceeds the random number's low 32
  /// bits: both below 2^32, the signed 64-bit compare is the unsigned 32-bit one.
  static Keep keeps(I choice, I random) {
    const __m512i low32 = _mm512_set1_epi64(0xFFFFFFFFll);
    return _mm512_cmpgt_epi64_mask(_mm512_and_si512(choice, low32), _mm512_and_si512(random, low32));
  }
  static I select(Keep keep, I yes, I no) { return _mm512_mask_blend_epi64(keep, no, yes); }
  static D select(Keep keep, D yes, D no) { return _mm512_mask_blend_pd(keep, no, yes); }

  /// Coefficients k to k + 3 of each lane's row (lane i's at from[at[i]]), a register per
  /// coefficient: eight loads (rows i and i + 4 in one register), the pairs of rows interleaved
  /// and the interleaved pairs merged (loads and shuffles cost less than gathers).
  static void rows(const double* from, const std::uint64_t* at, D* out) {
    auto both = [&](int i) {  // rows i and i + 4: (i, i + 4) halves
      return _mm512_insertf64x4(_mm512_castpd256_pd512(_mm256_loadu_pd(from + at[i])), _mm256_loadu_pd(from + at[i + 4]), 1);
    };
    const __m512d r04 = both(0), r15 = both(1), r26 = both(2), r37 = both(3);
    // Per 128-bit quarter q of t0: rows (0, 1)'s coefficient 2 * (q % 2) (rows 4, 5 in the upper half).
    const __m512d t0 = _mm512_unpacklo_pd(r04, r15), t1 = _mm512_unpackhi_pd(r04, r15);
    const __m512d t2 = _mm512_unpacklo_pd(r26, r37), t3 = _mm512_unpackhi_pd(r26, r37);
    const __m512i even = _mm512_setr_epi64(0, 1, 8, 9, 4, 5, 12, 13), odd = _mm512_setr_epi64(2, 3, 10, 11, 6, 7, 14, 15);
    out[0] = _mm512_permutex2var_pd(t0, even, t2);
    out[1] = _mm512_permutex2var_pd(t1, even, t3);
    out[2] = _mm512_permutex2var_pd(t0, odd, t2);
    out[3] = _mm512_permutex2var_pd(t1, odd, t3);
  }
  /// Rows of two doubles (2D offsets): the first of each lane's into x, the second into y. Lanes
  /// 0, 2, 4, 6 and 1, 3, 5, 7 side by side: their low and high halves are x's and y's.
  static void pairs(const double* from, const std::uint64_t* at, D& x, D& y) {
    auto two = [&](int i, int j) {
      return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(from + at[i])), _mm_loadu_pd(from + at[j]), 1);
    };
    const __m512d even = _mm512_insertf64x4(_mm512_castpd256_pd512(two(0, 2)), two(4, 6), 1);
    const __m512d odd = _mm512_insertf64x4(_mm512_castpd256_pd512(two(1, 3)), two(5, 7), 1);
    x = _mm512_unpacklo_pd(even, odd);
    y = _mm512_unpackhi_pd(even, odd);
  }

  /// Levels below 2^31, truncated to 32 bits.
  static void store_truncated(std::uint32_t* to, D x) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(to), _mm512_cvttpd_epi32(x));
  }
  static void store_rounded(float* to, D x) { _mm256_storeu_ps(to, _mm512_cvtpd_ps(x)); }
  /// Each lane's record word: 1 (its hit), then its three levels (below 2^31) truncated to 32
  /// bits, lane k's at to + 4 k; two permutes of the truncated levels and the ones.
  static void store_records(std::uint32_t* to, D level0, D level1, D level2) {
    const __m512i levels01 = _mm512_inserti64x4(_mm512_castsi256_si512(_mm512_cvttpd_epi32(level0)),
                                                _mm512_cvttpd_epi32(level1), 1);
    const __m512i levels2_ones = _mm512_inserti64x4(_mm512_castsi256_si512(_mm512_cvttpd_epi32(level2)),
                                                    _mm256_set1_epi32(1), 1);
    // Word k: the one (index 24), level 0 (k), level 1 (8 + k), level 2 (16 + k).
    const __m512i first = _mm512_setr_epi32(24, 0, 8, 16, 24, 1, 9, 17, 24, 2, 10, 18, 24, 3, 11, 19);
    const __m512i second = _mm512_setr_epi32(24, 4, 12, 20, 24, 5, 13, 21, 24, 6, 14, 22, 24, 7, 15, 23);
    _mm512_storeu_si512(to, _mm512_permutex2var_epi32(levels01, first, levels2_ones));
    _mm512_storeu_si512(to + 16, _mm512_permutex2var_epi32(levels01, second, levels2_ones));
  }
  /// A record word added to a pixel's record (four 32-bit sums); bit 1 + c set where channel c's
  /// sum wrapped (came out below what it took; the hits, flushed first, never do).
  static int add_record(std::uint32_t* record, const std::uint32_t* word) {
    const __m128i w = _mm_loadu_si128(reinterpret_cast<const __m128i*>(word));
    const __m128i sum = _mm_add_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(record)), w);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(record), sum);
    return _mm_mask_cmplt_epu32_mask(0xE, sum, w);
  }

  /// The frame's pixels: each lane's slot, the trash one off the image.
  struct Screen {
    __m512d zero, width, height;
    __m256i columns, trash;

    explicit Screen(const Maps& m)
        : zero(_mm512_setzero_pd()),
          width(_mm512_set1_pd(m.width)),
          height(_mm512_set1_pd(m.height)),
          columns(_mm256_set1_epi32(static_cast<int>(m.columns))),
          trash(_mm256_set1_epi32(static_cast<int>(m.trash))) {}

    void store(std::uint32_t* to, D px, D py) const {
      // Ordered compares: a NaN is outside, as in the general path.
      __mmask8 inside = _mm512_cmp_pd_mask(px, zero, _CMP_GE_OQ);
      inside = _mm512_mask_cmp_pd_mask(inside, px, width, _CMP_LT_OQ);
      inside = _mm512_mask_cmp_pd_mask(inside, py, zero, _CMP_GE_OQ);
      inside = _mm512_mask_cmp_pd_mask(inside, py, height, _CMP_LT_OQ);
      // Inside, both are in [0, 2^31): truncation is the general path's size_t conversion.
      const __m256i slot =
          _mm256_add_epi32(_mm256_mullo_epi32(_mm512_cvttpd_epi32(py), columns), _mm512_cvttpd_epi32(px));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(to), _mm256_mask_blend_epi32(inside, trash, slot));
    }
  };
};

}  // namespace
}  // namespace ifsforge::chains
