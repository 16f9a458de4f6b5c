// The lane kernel for any x86-64: the AVX2 kernel's arithmetic lane by lane, operation for
// operation (compiled with -ffp-contract=off, so the compiler fuses nothing on its own), and
// std::fma where that kernel fuses: a correctly rounded fused multiply-add on every CPU, so
// both kernels give the same bits. It includes nothing of the library but chaos_lanes.h.
#include <cmath>

#include "chaos_lanes.h"

namespace ifsforge::lanes {
namespace {

/// cvttps2dq: truncation toward zero; out of range (or NaN) gives INT32_MIN.
inline std::int32_t truncate(float x) {
  return x >= -2147483648.0f && x < 2147483648.0f ? static_cast<std::int32_t>(x) : INT32_MIN;
}

template <int N>
struct Lanes {
  float p[N][kWidth];
  std::uint32_t s[4][kWidth];

  void step(const Maps& m) {
    for (int k = 0; k < kWidth; ++k) {
      // xoshiro128+ (the AVX2 kernel's generator, one lane).
      const std::uint32_t result = s[0][k] + s[3][k];
      const std::uint32_t t = s[1][k] << 9;
      s[2][k] ^= s[0][k];
      s[3][k] ^= s[1][k];
      s[1][k] ^= s[2][k];
      s[0][k] ^= s[3][k];
      s[2][k] ^= t;
      s[3][k] = (s[3][k] << 11) | (s[3][k] >> 21);
      const auto u = static_cast<std::int32_t>(result >> 8);
      int index = 0;
      for (int j = 0; j + 1 < m.count; ++j) index += u > m.thresholds[j];
      float q[N];
      for (int r = 0; r < N; ++r) {
        float value = m.b[r][index];
        for (int c = N - 1; c >= 0; --c) value = std::fma(m.a[r * N + c][index], p[c][k], value);
        q[r] = value;
      }
      for (int r = 0; r < N; ++r) p[r][k] = q[r];
    }
  }

  std::uint32_t slot(int k, int width, int height) const {
    const std::int32_t ix = truncate(std::floor(p[0][k])), iy = truncate(std::floor(p[1][k]));
    const bool inside = ix > -1 && width > ix && iy > -1 && height > iy;
    return inside ? std::uint32_t(iy) * std::uint32_t(width) + std::uint32_t(ix) : std::uint32_t(width * height);
  }
};

template <int N>
void run(const Maps& maps, const Job& job) {
  Lanes<N> lanes[kGroups];
  for (int g = 0; g < kGroups; ++g)
    for (int k = 0; k < kWidth; ++k) {
      for (int c = 0; c < N; ++c) lanes[g].p[c][k] = job.origin[c];
      for (int w = 0; w < 4; ++w) lanes[g].s[w][k] = job.state[g][w][k];
    }
  for (std::uint64_t i = 0; i < job.skip; ++i)
    for (auto& l : lanes) l.step(maps);
  std::size_t filled = 0;  // slots in job.batch
  for (std::uint64_t i = 0; i < job.points / kLanes; ++i) {
    for (auto& l : lanes) {
      l.step(maps);
      for (int k = 0; k < kWidth; ++k) {
        const std::uint32_t s = l.slot(k, job.width, job.height);
        if (N == 2 && job.batch) {
          job.batch[filled++] = s;
        } else if constexpr (N == 3) {
          HitDepth& cell = job.cells[s];
          ++cell.hits;
          if (l.p[2][k] > cell.depth) cell.depth = l.p[2][k];
        } else {
          if (++job.low[s] == 0) __atomic_fetch_add(job.carry + s, 256, __ATOMIC_RELAXED);
        }
      }
    }
    if (job.batch && filled == job.batch_size) {
      job.flush(job.sink, job.batch, filled);
      filled = 0;
    }
  }
  if (filled) job.flush(job.sink, job.batch, filled);
}

}  // namespace

void run_baseline2(const Maps& maps, const Job& job) { run<2>(maps, job); }
void run_baseline3(const Maps& maps, const Job& job) { run<3>(maps, job); }

}  // namespace ifsforge::lanes
