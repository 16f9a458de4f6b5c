// The chain lanes for AVX2 (compiled with -mavx2 -mfma whatever the library's flags; run only
// where the CPU has both). Four chains per register of doubles, one or two registers; each lane
// performs the baseline kernel's operations in its order: separate multiplies and adds
// (-ffp-contract=off keeps the compiler from fusing them), so the bits are the same. It includes
// nothing of the library but chaos_chains.h, and its helpers have internal linkage.
#include "chaos_chains.h"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>

namespace ifsforge::chains {
namespace {

/// Which terms of the maps' linear parts are taken: all of them, the diagonal's
/// (Maps::diagonal), or a blocked one's with 2 or 3 spatial coordinates (Maps::blocked).
enum Shape { kDense, kDiagonal, kBlocked2, kBlocked3 };

/// Whether a linear part of shape kShape takes the term of row r, column c: a blocked row takes
/// the spatial columns, and a channel row its own too.
template <Shape kShape>
constexpr bool takes(int r, int c) {
  if constexpr (kShape == kDense) return true;
  if constexpr (kShape == kDiagonal) return r == c;
  return c < (kShape == kBlocked2 ? 2 : 3) || c == r;
}

/// x' = ((b + a0 x0) + a1 x1) + ...: the general path's order (a row by row), without the zero
/// terms that the shape leaves out.
template <int N, Shape kShape>
[[gnu::always_inline]] inline void affine(const __m256d* a, const __m256d* b, __m256d* p) {
  __m256d next[N];
  for (int r = 0; r < N; ++r) {
    __m256d value = b[r];
    for (int c = 0; c < N; ++c)
      if (takes<kShape>(r, c)) value = _mm256_add_pd(value, _mm256_mul_pd(a[r * N + c], p[c]));
    next[r] = value;
  }
  for (int r = 0; r < N; ++r) p[r] = next[r];
}

/// A linear part that every map shares, as constants.
template <int N, Shape kShape>
struct SharedA {
  __m256d a[N * N];

  explicit SharedA(const Maps& m) {
    for (int k = 0; k < N * N; ++k) a[k] = _mm256_set1_pd(m.coefficients[k]);
  }

  [[gnu::always_inline]] void apply(const __m256d* b, __m256d* p) const { affine<N, kShape>(a, b, p); }
};

/// The permute that takes map i's double (floats 2i and 2i + 1 of a table) into each lane.
[[gnu::always_inline]] inline __m256i pairs(__m256i map) {
  const __m256i twice = _mm256_slli_epi64(map, 1);
  return _mm256_or_si256(twice, _mm256_slli_epi64(_mm256_add_epi64(twice, _mm256_set1_epi64x(1)), 32));
}

/// Coefficients k to k + 3 of each lane's row (lane i's at from[at[i]]), a register per
/// coefficient: four loads and a 4x4 transpose (loads and shuffles cost less than gathers).
[[gnu::always_inline]] inline void transposed(const double* from, const std::uint64_t* at, __m256d* out) {
  const __m256d r0 = _mm256_loadu_pd(from + at[0]), r1 = _mm256_loadu_pd(from + at[1]);
  const __m256d r2 = _mm256_loadu_pd(from + at[2]), r3 = _mm256_loadu_pd(from + at[3]);
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  out[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
  out[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
  out[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
  out[3] = _mm256_permute2f128_pd(t1, t3, 0x31);
}

/// The draw of Coefficients and SharedLinear (Quad::choose: a gather of each lane's choice; with
/// at most four maps, permutes and blends of the choices held in registers gained at most 2% and
/// cost a recurrent system 8%), and their map applied to the quad.
template <class Self>
struct FromChoices {
  template <class Q>
  [[gnu::always_inline]] void choose(Q& q, const Maps& m, __m256i count) const {
    q.choose(m, count);
  }
  template <class Q>
  void apply(Q& q) const {
    static_cast<const Self&>(*this).apply_to(q.map, q.p);
  }
};

/// Each lane's map's coefficients (a row by row, then b), for four lanes at once. A coefficient
/// that every map shares (the same bits: similitudes of one ratio share their a) is a constant;
/// the others, with at most four maps, come from registers that hold every map's (a permute
/// each), else from each lane's row, loaded, the four rows transposed a register at a time
/// (loads and shuffles cost less than gathers). Only the terms of the maps' shape are applied
/// (and, from registers, fetched): a colour fern's channels are blocked in every map.
template <int N, bool kFew, Shape kShape>
struct Coefficients : FromChoices<Coefficients<N, kFew, kShape>> {
  static constexpr int kCount = N * N + N;
  static constexpr int kPadded = (kCount + 3) / 4 * 4;  // whole registers
  __m256d shared[kPadded];  // map 0's, broadcast
  __m256d tables[kFew ? kCount : 1];
  bool varies[kPadded];  // kFew: per coefficient; else per register of four
  const double* rows;
  long long stride;  // kPadded, as Plan lays the rows out

  explicit Coefficients(const Maps& m) : rows(m.coefficients), stride(m.stride) {
    for (int k = 0; k < kPadded; ++k) {
      shared[k] = _mm256_set1_pd(rows[k]);
      varies[k] = false;
      for (int i = 1; i < m.count; ++i) varies[k] |= __builtin_memcmp(rows + i * stride + k, rows + k, sizeof(double)) != 0;
    }
    if constexpr (kFew) {
      for (int k = 0; k < kCount; ++k) {
        alignas(32) double across[kWidth] = {};
        for (int i = 0; i < m.count; ++i) across[i] = rows[i * stride + k];
        tables[k] = _mm256_load_pd(across);
      }
    } else {
      for (int j = 0; j < kPadded; j += 4) varies[j] = varies[j] || varies[j + 1] || varies[j + 2] || varies[j + 3];
    }
  }

  void apply_to(__m256i map, __m256d* p) const {
    __m256d k[kPadded];
    fetch(map, k);
    affine<N, kShape>(k, k + N * N, p);
  }

  void fetch(__m256i map, __m256d* out) const {
    if constexpr (kFew) {
      const __m256i pair = pairs(map);
#pragma GCC unroll 80
      for (int k = 0; k < kCount; ++k)  // only the terms the shape takes, and the offsets
        if (k >= N * N || takes<kShape>(k / N, k % N))
          out[k] = varies[k] ? _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(tables[k]), pair)) : shared[k];
    } else {
      alignas(32) std::uint64_t at[kWidth];
      _mm256_store_si256(reinterpret_cast<__m256i*>(at), _mm256_mul_epu32(map, _mm256_set1_epi64x(stride)));
#pragma GCC unroll 20
      for (int j = 0; j < kPadded; j += 4) {
        if (!varies[j]) {
          for (int k = j; k < j + 4; ++k) out[k] = shared[k];
          continue;
        }
        transposed(rows + j, at, out + j);
      }
    }
  }
};

template <int N, Shape kShape>
using FewCoefficients = Coefficients<N, true, kShape>;
template <int N, Shape kShape>
using ManyCoefficients = Coefficients<N, false, kShape>;

/// At most four maps that share their linear part (the same bits: similitudes of one ratio, the
/// colour samples' channel rows): the a are constants and only the offsets b differ from lane to
/// lane, each from a permute.
template <int N, Shape kShape>
struct SharedLinear : FromChoices<SharedLinear<N, kShape>> {
  SharedA<N, kShape> a;
  __m256d tables[N];

  explicit SharedLinear(const Maps& m) : a(m) {
    for (int r = 0; r < N; ++r) {
      alignas(32) double across[kWidth] = {};
      for (int i = 0; i < m.count; ++i) across[i] = m.coefficients[i * m.stride + N * N + r];
      tables[r] = _mm256_load_pd(across);
    }
  }

  void apply_to(__m256i map, __m256d* p) const {
    const __m256i pair = pairs(map);
    __m256d b[N];
    for (int r = 0; r < N; ++r) b[r] = _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(tables[r]), pair));
    a.apply(b, p);
  }
};

/// Four chains: their points, xoshiro256+ states and current maps.
template <int N>
struct Quad {
  __m256d p[N];
  __m256i s0, s1, s2, s3, map;

  [[gnu::always_inline]] __m256i next() {
    const __m256i result = _mm256_add_epi64(s0, s3);
    const __m256i t = _mm256_slli_epi64(s1, 17);
    s2 = _mm256_xor_si256(s2, s0);
    s3 = _mm256_xor_si256(s3, s1);
    s1 = _mm256_xor_si256(s1, s2);
    s0 = _mm256_xor_si256(s0, s3);
    s2 = _mm256_xor_si256(s2, t);
    s3 = _mm256_or_si256(_mm256_slli_epi64(s3, 45), _mm256_srli_epi64(s3, 19));
    return result;
  }

  __m256d b[N];  // SharedDraws: the offsets of the map drawn for the next step

  /// MapSampler's draw from the row of the current map (row 0 unless recurrent): the random
  /// number, its column, and the draw's index in Maps::choices.
  [[gnu::always_inline]] __m256i draw(const Maps& m, __m256i count, __m256i& random, __m256i& column) {
    random = next();
    column = _mm256_srli_epi64(_mm256_mul_epu32(_mm256_srli_epi64(random, 32), count), 32);
    return m.recurrent ? _mm256_add_epi64(_mm256_mul_epu32(map, count), column) : column;
  }

  /// Whether each lane keeps its column (else takes the alias), and the map it takes.
  [[gnu::always_inline]] __m256i pick(__m256i choice, __m256i random, __m256i column) {
    const __m256i low32 = _mm256_set1_epi64x(0xFFFFFFFFll);
    // Both sides below 2^32: the signed 64-bit compare is the unsigned 32-bit one.
    const __m256i keep = _mm256_cmpgt_epi64(_mm256_and_si256(choice, low32), _mm256_and_si256(random, low32));
    map = _mm256_blendv_epi8(_mm256_srli_epi64(choice, 32), column, keep);
    return keep;
  }

  [[gnu::always_inline]] void choose(const Maps& m, __m256i count) {
    __m256i random, column;
    const __m256i at = draw(m, count, random, column);
    if (m.own_columns) {  // the pick takes the column or its alias: the column either way
      map = column;
      return;
    }
    pick(_mm256_i64gather_epi64(reinterpret_cast<const long long*>(m.choices), at, 8), random, column);
  }
};

/// More than four maps that share their linear part: each lane's draw loads its row of
/// Maps::draws (transposed, four lanes at once), which gives the choice and the offsets of both
/// maps it may pick, so the map and its offsets come without a gather (slow on some CPUs) and
/// without waiting on each other. The offsets wait in the quad for the next step's apply. Where
/// every draw keeps its column (kDirect: Maps::direct) the column is the map and the row holds
/// only its offsets, two rows of 2D ones to a register.
template <int N, Shape kShape, bool kDirect>
struct SharedDraws {
  static constexpr int kRow = kDirect ? offsets_row(N) : draw_row(N);
  SharedA<N, kShape> a;
  const double* draws;

  explicit SharedDraws(const Maps& m) : a(m), draws(m.draws) {}

  template <class Q>
  [[gnu::always_inline]] void choose(Q& q, const Maps& m, __m256i count) const {
    __m256i random, column;
    alignas(32) std::uint64_t at[kWidth];
    _mm256_store_si256(reinterpret_cast<__m256i*>(at),
                       _mm256_mul_epu32(q.draw(m, count, random, column), _mm256_set1_epi64x(kRow)));
    if constexpr (kDirect && kRow == 2) {
      // Lanes 0 and 2, 1 and 3 side by side: their low and high halves are x's and y's offsets.
      const __m256d even = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(draws + at[0])),
                                                _mm_loadu_pd(draws + at[2]), 1);
      const __m256d odd = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(draws + at[1])),
                                               _mm_loadu_pd(draws + at[3]), 1);
      q.map = column;
      q.b[0] = _mm256_unpacklo_pd(even, odd);
      q.b[1] = _mm256_unpackhi_pd(even, odd);
      return;
    }
    __m256d row[kRow];
    for (int j = 0; j < kRow; j += 4) transposed(draws + j, at, row + j);
    if constexpr (kDirect) {
      q.map = column;
      for (int r = 0; r < N; ++r) q.b[r] = row[r];
    } else {
      const __m256d keep = _mm256_castsi256_pd(q.pick(_mm256_castpd_si256(row[0]), random, column));
      for (int r = 0; r < N; ++r) q.b[r] = _mm256_blendv_pd(row[1 + N + r], row[1 + r], keep);
    }
  }

  template <class Q>
  void apply(Q& q) const {
    a.apply(q.b, q.p);
  }
};

template <int N, Shape kShape>
using SharedLinearDraws = SharedDraws<N, kShape, false>;
template <int N, Shape kShape>
using SharedLinearOffsets = SharedDraws<N, kShape, true>;

template <int N, int G, class Coefficients>
void run(const Maps& m, const Job& job) {
  constexpr int kTerms = N < 3 ? N : 3;
  const Coefficients coefficients(m);
  Quad<N> quads[G];
  for (int g = 0; g < G; ++g) {
    alignas(32) std::uint64_t s[4][kWidth], map[kWidth];
    for (int k = 0; k < kWidth; ++k) {
      const int chain = g * kWidth + k < job.chains ? g * kWidth + k : 0;  // spare lanes copy chain 0
      for (int w = 0; w < 4; ++w) s[w][k] = job.rng[chain][w];
      map[k] = job.map[chain];
    }
    Quad<N>& q = quads[g];
    for (int c = 0; c < N; ++c) q.p[c] = _mm256_set1_pd(job.start[c]);
    q.s0 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[0]));
    q.s1 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[1]));
    q.s2 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[2]));
    q.s3 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[3]));
    q.map = _mm256_load_si256(reinterpret_cast<const __m256i*>(map));
  }
  const __m256i count = _mm256_set1_epi64x(m.count);
  // Each step's map is drawn a step ahead (after the previous point's map was applied): the same
  // draws in the same order, one more at the end, unused; the draw and its loads then overlap
  // the arithmetic of the point before.
  for (auto& q : quads) coefficients.choose(q, m, count);
  for (std::uint64_t i = 0; i < job.skip; ++i)
    for (auto& q : quads) {
      coefficients.apply(q);
      coefficients.choose(q, m, count);
    }
  const __m256d zero = _mm256_setzero_pd(), width = _mm256_set1_pd(m.width), height = _mm256_set1_pd(m.height);
  const __m128i columns = _mm_set1_epi32(static_cast<int>(m.columns)), trash = _mm_set1_epi32(static_cast<int>(m.trash));
  const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
  const int channels = m.dim - m.spatial;
  __m256d lo[kMaxDim], scale[kMaxDim];
  for (int c = 0; c < channels; ++c) {
    lo[c] = _mm256_set1_pd(m.lo[c]);
    scale[c] = _mm256_set1_pd(m.scale[c]);
  }
  const __m256d steps = _mm256_set1_pd(m.steps), half = _mm256_set1_pd(0.5);
  Batches batches(job, channels);
  for (std::uint64_t i = 0; i < job.points; ++i) {
    std::uint32_t* slots = batches.slots();
    std::uint32_t* levels = batches.levels();
    float* depths = batches.depths();
    const std::size_t filled = batches.filled();
    for (int g = 0; g < G; ++g) {
      Quad<N>& q = quads[g];
      coefficients.apply(q);
      coefficients.choose(q, m, count);
      __m256d px = _mm256_set1_pd(m.u0), py = _mm256_set1_pd(m.v0);
      if (m.planar) {
        px = _mm256_add_pd(px, _mm256_mul_pd(_mm256_set1_pd(m.u[0]), q.p[0]));
        py = _mm256_add_pd(py, _mm256_mul_pd(_mm256_set1_pd(m.v[1]), q.p[1]));
      } else {
        for (int t = 0; t < kTerms; ++t) {
          px = _mm256_add_pd(px, _mm256_mul_pd(_mm256_set1_pd(m.u[t]), q.p[t]));
          py = _mm256_add_pd(py, _mm256_mul_pd(_mm256_set1_pd(m.v[t]), q.p[t]));
        }
      }
      // Ordered compares: a NaN is outside, as in the general path.
      const __m256d inside = _mm256_and_pd(
          _mm256_and_pd(_mm256_cmp_pd(px, zero, _CMP_GE_OQ), _mm256_cmp_pd(px, width, _CMP_LT_OQ)),
          _mm256_and_pd(_mm256_cmp_pd(py, zero, _CMP_GE_OQ), _mm256_cmp_pd(py, height, _CMP_LT_OQ)));
      const __m128i in32 =
          _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(_mm256_castpd_si256(inside), low_halves));
      // Inside, both are in [0, 2^31): truncation is the general path's size_t conversion.
      const __m128i slot =
          _mm_add_epi32(_mm_mullo_epi32(_mm256_cvttpd_epi32(py), columns), _mm256_cvttpd_epi32(px));
      const std::size_t at = filled + g * kWidth;
      const __m128i slot4 = _mm_blendv_epi8(trash, slot, in32);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(slots + at), slot4);
      // The slots read back from the batch (loads cost less than extracting each lane).
      for (int k = 0; k < kWidth; ++k) _mm_prefetch(job.counters + slots[at + k] * job.counter_bytes, _MM_HINT_T0);
      // Accumulator::quantised: q < 0 ? 0 : min(q, steps) is max(q, 0) then the min (a zero of
      // either sign gives level 0 both ways), and the levels are below 2^31: truncation to 32 bits
      // is the conversion to 64.
      for (int c = 0; c < channels; ++c) {
        const __m256d level = _mm256_mul_pd(_mm256_sub_pd(q.p[m.spatial + c], lo[c]), scale[c]);
        const __m256d clamped = _mm256_min_pd(_mm256_max_pd(level, zero), steps);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(levels + c * kStride + at),
                         _mm256_cvttpd_epi32(_mm256_add_pd(clamped, half)));
      }
      if constexpr (N >= 3)
        if (m.spatial == 3) {  // rounded to float as Accumulator::add_depth
          const __m256d depth = _mm256_add_pd(
              _mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(m.toward[0]), q.p[0]),
                            _mm256_mul_pd(_mm256_set1_pd(m.toward[1]), q.p[1])),
              _mm256_mul_pd(_mm256_set1_pd(m.toward[2]), q.p[2]));
          _mm_storeu_ps(depths + at, _mm256_cvtpd_ps(depth));
        }
    }
    batches.advance(job.chains);
  }
  batches.finish();
}

template <int N, class Coefficients>
void run_with(const Maps& m, const Job& job) {
  (job.chains > kWidth ? run<N, 2, Coefficients> : run<N, 1, Coefficients>)(m, job);
}

/// The kernel for the maps' linear parts' shape: diagonal (similitudes without rotation, in 2D
/// and 3D), blocked (a colour system's channels), or dense.
template <int N, template <int, Shape> class Kind>
void run_shaped(const Maps& m, const Job& job) {
  if constexpr (N <= 3)
    if (m.diagonal) return run_with<N, Kind<N, kDiagonal>>(m, job);
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
  else if (m.count <= kWidth)
    m.shared_linear ? run_shaped<N, SharedLinear>(m, job) : run_shaped<N, FewCoefficients>(m, job);
  else
    run_shaped<N, ManyCoefficients>(m, job);
}

}  // namespace

void run_avx2(const Maps& m, const Job& job) {
  using Run = void (*)(const Maps&, const Job&);
  static constexpr Run kRuns[] = {run_dim<2>, run_dim<3>, run_dim<4>, run_dim<5>,
                                  run_dim<6>, run_dim<7>, run_dim<8>};
  kRuns[m.dim - 2](m, job);
}

}  // namespace ifsforge::chains

#else  // not x86-64: the host never picks this

namespace ifsforge::chains {
void run_avx2(const Maps& m, const Job& job) { run_baseline(m, job); }
}  // namespace ifsforge::chains

#endif
