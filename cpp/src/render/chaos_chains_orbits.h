#pragma once
// The chain lanes' orbits (chaos_chains.h), written once for every vector width: each lane's
// xoshiro256+ stream, its MapChain draw and its map applied with the general path's operations in
// its order (no fused multiply-add), for kLanes chains per register. A unit compiled for one
// instruction set defines `V` (chaos_chains_avx2.h, chaos_chains_avx512.h) in the anonymous
// namespace of ifsforge::chains, then includes this file, so that everything here is compiled for
// that set and has internal linkage. The chaos game's kernel (chaos_chains_kernel.h) projects the
// points to pixels; the random-iteration volume's (volume/voxel_chains_kernel.h) finds their voxels.
#include <immintrin.h>

#include <cstdint>

#include "chaos_chains.h"

namespace ifsforge::chains {
namespace {

/// Which terms of the maps' linear parts are taken: all of them, the diagonal's
/// (Maps::diagonal), a blocked one's with 2 or 3 spatial coordinates (Maps::blocked), or a 2D
/// blocked one's whose channels take the height only (Maps::by_height).
enum Shape { kDense, kDiagonal, kBlocked2, kBlocked3, kHeight2 };

/// Whether a linear part of shape kShape takes the term of row r, column c: a blocked row takes
/// the spatial columns, and a channel row its own too; by height, a channel row takes y (column
/// 1) and its own.
template <Shape kShape>
constexpr bool takes(int r, int c) {
  if constexpr (kShape == kDense) return true;
  if constexpr (kShape == kDiagonal) return r == c;
  if constexpr (kShape == kHeight2) return r < 2 ? c < 2 : c == 1 || c == r;
  return c < (kShape == kBlocked2 ? 2 : 3) || c == r;
}

using D = V::D;  ///< kLanes doubles
using I = V::I;  ///< kLanes 64-bit integers
constexpr int kLanes = V::kLanes;
/// Registers of chains per step: kMaxChains chains in flight, to hide the map's latency.
constexpr int kGroups = kMaxChains / kLanes;

/// x' = ((b + a0 x0) + a1 x1) + ...: the general path's order (a row by row), without the zero
/// terms that the shape leaves out.
template <int N, Shape kShape>
[[gnu::always_inline]] inline void affine(const D* a, const D* b, D* p) {
  D next[N];
  for (int r = 0; r < N; ++r) {
    D value = b[r];
    for (int c = 0; c < N; ++c)
      if (takes<kShape>(r, c)) value = V::add(value, V::mul(a[r * N + c], p[c]));
    next[r] = value;
  }
  for (int r = 0; r < N; ++r) p[r] = next[r];
}

/// A linear part that every map shares, as constants.
template <int N, Shape kShape>
struct SharedA {
  D a[N * N];

  explicit SharedA(const Maps& m) {
    for (int k = 0; k < N * N; ++k) a[k] = V::set1(m.coefficients[k]);
  }

  [[gnu::always_inline]] void apply(const D* b, D* p) const { affine<N, kShape>(a, b, p); }
};

/// The draw of Coefficients and SharedLinear (Quad::choose: a gather of each lane's choice), and
/// their map applied to the quad. Without recurrence and with at most kLanes maps whose draws
/// may take an alias, the one row of choices is a register, each lane's a permute (a gather
/// was 14% of the colour fern's kernel on AVX-512; on AVX2 permutes and blends of choices in
/// registers gained at most 2% and cost a recurrent system 8%, so recurrent rows still gather).
template <class Self>
struct FromChoices {
  D choices;      // map i's choice's bits in lane i
  bool in_table;  // the draw reads `choices`

  explicit FromChoices(const Maps& m) : in_table(!m.recurrent && !m.own_columns && m.count <= kLanes) {
    alignas(sizeof(D)) std::uint64_t row[kLanes] = {};
    for (int i = 0; i < m.count && in_table; ++i) row[i] = m.choices[i];
    choices = V::doubles(V::load(row));
  }

  template <class Q>
  [[gnu::always_inline]] void choose(Q& q, const Maps& m, I count) const {
    if (!in_table) return q.choose(m, count);
    I random, column;
    q.draw(m, count, random, column);
    q.pick(V::bits(V::lookup(choices, V::index(column))), random, column);
  }
  template <class Q>
  void apply(Q& q) const {
    static_cast<const Self&>(*this).apply_to(q.map, q.p);
  }
};

/// Each lane's map's coefficients (a row by row, then b), for every lane at once. With at most
/// kLanes maps, each comes from a register that holds every map's (a permute each, also for a
/// coefficient every map shares: a branch per coefficient and step to take a constant instead
/// cost the colour fern more than the permute); else from each lane's row, loaded, the rows
/// transposed four coefficients at a time (loads and shuffles cost less than gathers), or a
/// constant where every map shares all four (the same bits: similitudes of one ratio share
/// their a). Only the terms of the maps' shape are applied (and, from registers, fetched): a
/// colour fern's channels are blocked in every map, and take the height only.
template <int N, bool kFew, Shape kShape>
struct Coefficients : FromChoices<Coefficients<N, kFew, kShape>> {
  static constexpr int kCount = N * N + N;
  static constexpr int kPadded = (kCount + 3) / 4 * 4;  // whole rows of four, as Plan pads them
  D shared[kPadded];  // map 0's, broadcast
  D tables[kFew ? kCount : 1];
  bool varies[kPadded];  // !kFew: per four, at the first (some map's bits differ from map 0's)
  const double* rows;
  long long stride;  // kPadded, as Plan lays the rows out

  explicit Coefficients(const Maps& m)
      : FromChoices<Coefficients<N, kFew, kShape>>(m), rows(m.coefficients), stride(m.stride) {
    for (int k = 0; k < kPadded; ++k) {
      shared[k] = V::set1(rows[k]);
      varies[k] = false;
      for (int i = 1; i < m.count; ++i) varies[k] |= __builtin_memcmp(rows + i * stride + k, rows + k, sizeof(double)) != 0;
    }
    if constexpr (kFew) {
      for (int k = 0; k < kCount; ++k) {
        alignas(sizeof(D)) double across[kLanes] = {};
        for (int i = 0; i < m.count; ++i) across[i] = rows[i * stride + k];
        tables[k] = V::load(across);
      }
    } else {
      for (int j = 0; j < kPadded; j += 4) varies[j] = varies[j] || varies[j + 1] || varies[j + 2] || varies[j + 3];
    }
  }

  void apply_to(I map, D* p) const {
    D k[kPadded];
    fetch(map, k);
    affine<N, kShape>(k, k + N * N, p);
  }

  void fetch(I map, D* out) const {
    if constexpr (kFew) {
      const V::Index index = V::index(map);
#pragma GCC unroll 80
      for (int k = 0; k < kCount; ++k)  // only the terms the shape takes, and the offsets
        if (k >= N * N || takes<kShape>(k / N, k % N)) out[k] = V::lookup(tables[k], index);
    } else {
      alignas(sizeof(D)) std::uint64_t at[kLanes];
      V::store(at, V::mul_low(map, V::set1(stride)));
#pragma GCC unroll 20
      for (int j = 0; j < kPadded; j += 4) {
        if (!varies[j]) {
          for (int k = j; k < j + 4; ++k) out[k] = shared[k];
          continue;
        }
        V::rows(rows + j, at, out + j);
      }
    }
  }
};

template <int N, Shape kShape>
using FewCoefficients = Coefficients<N, true, kShape>;
template <int N, Shape kShape>
using ManyCoefficients = Coefficients<N, false, kShape>;

/// At most kLanes maps that share their linear part (the same bits: similitudes of one ratio, the
/// colour samples' channel rows): the a are constants and only the offsets b differ from lane to
/// lane, each from a permute.
template <int N, Shape kShape>
struct SharedLinear : FromChoices<SharedLinear<N, kShape>> {
  SharedA<N, kShape> a;
  D tables[N];

  explicit SharedLinear(const Maps& m) : FromChoices<SharedLinear<N, kShape>>(m), a(m) {
    for (int r = 0; r < N; ++r) {
      alignas(sizeof(D)) double across[kLanes] = {};
      for (int i = 0; i < m.count; ++i) across[i] = m.coefficients[i * m.stride + N * N + r];
      tables[r] = V::load(across);
    }
  }

  void apply_to(I map, D* p) const {
    const V::Index index = V::index(map);
    D b[N];
    for (int r = 0; r < N; ++r) b[r] = V::lookup(tables[r], index);
    a.apply(b, p);
  }
};

/// kLanes chains: their points, xoshiro256+ states and current maps.
template <int N>
struct Quad {
  D p[N];
  I s0, s1, s2, s3, map;

  [[gnu::always_inline]] I next() {
    const I result = V::add(s0, s3);
    const I t = V::shift_left<17>(s1);
    s2 = V::bit_xor(s2, s0);
    s3 = V::bit_xor(s3, s1);
    s1 = V::bit_xor(s1, s2);
    s0 = V::bit_xor(s0, s3);
    s2 = V::bit_xor(s2, t);
    s3 = V::rotate_left<45>(s3);
    return result;
  }

  D b[N];  // SharedDraws: the offsets of the map drawn for the next step

  /// MapSampler's draw from the row of the current map (row 0 unless recurrent): the random
  /// number, its column, and the draw's index in Maps::choices.
  [[gnu::always_inline]] I draw(const Maps& m, I count, I& random, I& column) {
    random = next();
    column = V::shift_right<32>(V::mul_low(V::shift_right<32>(random), count));
    return m.recurrent ? V::add(V::mul_low(map, count), column) : column;
  }

  /// Whether each lane keeps its column (else takes the alias), and the map it takes.
  [[gnu::always_inline]] V::Keep pick(I choice, I random, I column) {
    const V::Keep keep = V::keeps(choice, random);
    map = V::select(keep, column, V::shift_right<32>(choice));
    return keep;
  }

  [[gnu::always_inline]] void choose(const Maps& m, I count) {
    I random, column;
    const I at = draw(m, count, random, column);
    if (m.own_columns) {  // the pick takes the column or its alias: the column either way
      map = column;
      return;
    }
    pick(V::gather(m.choices, at), random, column);
  }
};

/// More than four maps that share their linear part: each lane's draw loads its row of
/// Maps::draws (transposed, every lane at once), which gives the choice and the offsets of both
/// maps it may pick, so the map and its offsets come without a gather (slow on some CPUs) and
/// without waiting on each other. The offsets wait in the quad for the next step's apply. Where
/// every draw keeps its column (kDirect: Maps::direct) the column is the map and the row holds
/// only its offsets, 2D ones two doubles a row.
template <int N, Shape kShape, bool kDirect>
struct SharedDraws {
  static constexpr int kRow = kDirect ? offsets_row(N) : draw_row(N);
  SharedA<N, kShape> a;
  const double* draws;

  explicit SharedDraws(const Maps& m) : a(m), draws(m.draws) {}

  template <class Q>
  [[gnu::always_inline]] void choose(Q& q, const Maps& m, I count) const {
    I random, column;
    alignas(sizeof(D)) std::uint64_t at[kLanes];
    V::store(at, V::mul_low(q.draw(m, count, random, column), V::set1(static_cast<long long>(kRow))));
    if constexpr (kDirect && kRow == 2) {
      q.map = column;
      V::pairs(draws, at, q.b[0], q.b[1]);
      return;
    }
    D row[kRow];
    for (int j = 0; j < kRow; j += 4) V::rows(draws + j, at, row + j);
    if constexpr (kDirect) {
      q.map = column;
      for (int r = 0; r < N; ++r) q.b[r] = row[r];
    } else {
      const V::Keep keep = q.pick(V::bits(row[0]), random, column);
      for (int r = 0; r < N; ++r) q.b[r] = V::select(keep, row[1 + r], row[1 + N + r]);
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

/// Quads g = 0 .. G - 1 start chains g * kLanes + k of `job` (their start, streams and maps) and
/// walk them through its skipped steps. Each step's map is drawn a step ahead (after the previous
/// point's map was applied): the same draws in the same order, one more at the end, unused; the
/// draw and its loads then overlap the arithmetic of the point before. So each step that
/// follows is coefficients.apply(q), then coefficients.choose(q, m, count).
template <int N, int G, class Coefficients>
void start_quads(const Coefficients& coefficients, const Maps& m, const Job& job, I count, Quad<N> (&quads)[G]) {
  for (int g = 0; g < G; ++g) {
    alignas(sizeof(D)) std::uint64_t s[4][kLanes], map[kLanes];
    for (int k = 0; k < kLanes; ++k) {
      const int chain = g * kLanes + k < job.chains ? g * kLanes + k : 0;  // spare lanes copy chain 0
      for (int w = 0; w < 4; ++w) s[w][k] = job.rng[chain][w];
      map[k] = job.map[chain];
    }
    Quad<N>& q = quads[g];
    for (int c = 0; c < N; ++c) q.p[c] = V::set1(job.start[c]);
    q.s0 = V::load(s[0]);
    q.s1 = V::load(s[1]);
    q.s2 = V::load(s[2]);
    q.s3 = V::load(s[3]);
    q.map = V::load(map);
  }
  for (auto& q : quads) coefficients.choose(q, m, count);
  for (std::uint64_t i = 0; i < job.skip; ++i)
    for (auto& q : quads) {
      coefficients.apply(q);
      coefficients.choose(q, m, count);
    }
}

}  // namespace
}  // namespace ifsforge::chains
