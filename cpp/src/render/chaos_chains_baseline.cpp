// The chain lanes for any x86-64: each chain's step written out as the general path takes it
// (chaos_game.cpp: MapSampler's draw, b + a x term by term, the projection term by term), the
// chains side by side in each step so that their latencies overlap. Compiled with
// -ffp-contract=off like the whole library: the AVX2 kernel's separate multiplies and adds are
// these; the channels quantised and the depth rounded as the accumulator does (chaos_chains.h).
// It includes nothing of the library but chaos_chains.h.
#include "chaos_chains.h"

namespace ifsforge::chains {
namespace {

/// A batch into Job::records: each point's hit and three levels added to its pixel's record, a
/// sum below its level wrapped (as ChannelSink::add_levels).
struct ToRecords {
  static void add(const Job& job, const std::uint32_t* slots, const std::uint32_t* levels, const float*,
                  std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t* record = job.records + std::size_t(slots[i]) * 4;
      ++record[0];
      for (int c = 0; c < 3; ++c) {
        const std::uint32_t q = levels[c * kStride + i], sum = record[1 + c] + q;
        if (sum < q) __atomic_fetch_add(job.carry + std::size_t(slots[i]) * 3 + c, std::uint64_t(1) << 32, __ATOMIC_RELAXED);
        record[1 + c] = sum;
      }
    }
  }
};

template <int N, class Add>
void run(const Maps& m, const Job& job) {
  constexpr int kTerms = N < 3 ? N : 3;
  const int chains = job.chains;
  double p[kMaxChains][N];
  std::uint64_t s[kMaxChains][4];
  std::uint32_t map[kMaxChains];
  for (int k = 0; k < chains; ++k) {
    for (int c = 0; c < N; ++c) p[k][c] = job.start[c];
    for (int w = 0; w < 4; ++w) s[k][w] = job.rng[k][w];
    map[k] = job.map[k];
  }
  auto step = [&](int k) {
    std::uint64_t* st = s[k];  // xoshiro256+ (core/random.h)
    const std::uint64_t random = st[0] + st[3];
    const std::uint64_t t = st[1] << 17;
    st[2] ^= st[0];
    st[3] ^= st[1];
    st[1] ^= st[2];
    st[0] ^= st[3];
    st[2] ^= t;
    st[3] = (st[3] << 45) | (st[3] >> 19);
    const auto column = static_cast<std::uint32_t>(((random >> 32) * std::uint64_t(m.count)) >> 32);
    const std::uint64_t choice = m.choices[(m.recurrent ? map[k] * std::uint64_t(m.count) : 0) + column];
    map[k] = static_cast<std::uint32_t>(random) < static_cast<std::uint32_t>(choice) ? column
                                                                                      : std::uint32_t(choice >> 32);
    const double* a = m.coefficients + std::size_t(map[k]) * m.stride;
    double q[N];
    for (int r = 0; r < N; ++r) {
      double value = a[N * N + r];
      for (int c = 0; c < N; ++c) value += a[r * N + c] * p[k][c];
      q[r] = value;
    }
    for (int c = 0; c < N; ++c) p[k][c] = q[c];
  };
  for (std::uint64_t i = 0; i < job.skip; ++i)
    for (int k = 0; k < chains; ++k) step(k);
  const int channels = m.dim - m.spatial;
  Batches<Add> batches(job, channels);
  for (std::uint64_t i = 0; i < job.points; ++i) {
    std::uint32_t* slots = batches.slots();
    std::uint32_t* levels = batches.levels();
    float* depths = batches.depths();
    std::size_t filled = batches.filled();
    for (int k = 0; k < chains; ++k) {
      step(k);
      double px = m.u0, py = m.v0;
      for (int t = 0; t < kTerms; ++t) {
        px += m.u[t] * p[k][t];
        py += m.v[t] * p[k][t];
      }
      const bool inside = px >= 0.0 && px < m.width && py >= 0.0 && py < m.height;
      slots[filled] = inside ? std::uint32_t(py) * m.columns + std::uint32_t(px) : m.trash;
      __builtin_prefetch(job.counters + slots[filled] * job.counter_bytes);
      for (int c = 0; c < channels; ++c) {  // Accumulator::quantised
        double q = (p[k][m.spatial + c] - m.lo[c]) * m.scale[c];
        q = q < 0.0 ? 0.0 : (q > m.steps ? m.steps : q);
        levels[c * kStride + filled] = static_cast<std::uint32_t>(static_cast<std::uint64_t>(q + 0.5));
      }
      if constexpr (N >= 3)
        if (m.spatial == 3)  // Accumulator::add_depth's float
          depths[filled] = static_cast<float>(m.toward[0] * p[k][0] + m.toward[1] * p[k][1] + m.toward[2] * p[k][2]);
      ++filled;
    }
    batches.advance(chains);
  }
  batches.finish();
}

}  // namespace

void run_baseline(const Maps& m, const Job& job) {
  using Run = void (*)(const Maps&, const Job&);
  static constexpr Run kRuns[] = {run<2, ToSink>, run<3, ToSink>, run<4, ToSink>, run<5, ToSink>,
                                  run<6, ToSink>, run<7, ToSink>, run<8, ToSink>};
  if (job.records) return run<5, ToRecords>(m, job);  // Job::records: 5D, two of them spatial
  kRuns[m.dim - 2](m, job);
}

}  // namespace ifsforge::chains
