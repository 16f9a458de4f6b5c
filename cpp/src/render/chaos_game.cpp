#include "ifsforge/render/chaos_game.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define IFSFORGE_CHAOS_AVX2 1
#endif

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/fixed_maps.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "polar_render.h"

namespace ifsforge {
namespace {

constexpr std::uint64_t kPointsPerJob = 1u << 22;

struct JobPlan {
  std::uint64_t jobs, points_per_job;
};

JobPlan plan_jobs(std::uint64_t total, std::uint64_t lanes) {
  const std::uint64_t jobs = std::max<std::uint64_t>(1, (total + kPointsPerJob - 1) / kPointsPerJob);
  std::uint64_t per_job = (total + jobs - 1) / jobs;
  per_job = (per_job + lanes - 1) / lanes * lanes;
  return {jobs, per_job};
}

/// The general nD path: double precision, any layout, channels carried. The dimension is a
/// template parameter so the map and the projection unroll (a runtime loop cannot).
/// The maps come from the walker's chain (model/orbit.h): a recurrent system (3.3.1) draws
/// each from the row of the map before it.
template <int N>
void chaos_job_fixed(const Ifs& ifs, const Frame& frame, const MapChain& chain, std::uint64_t points,
                     std::uint64_t skip, std::uint64_t seed, std::uint64_t job, Accumulator& acc) {
  constexpr int kSpatialMax = N < 3 ? N : 3;
  const auto maps = fixed_maps<N>(ifs);
  // Pixel coordinates straight from the spatial coordinates: px = U . x + u0, py = V . x + v0.
  const int spatial = ifs.spatial_dims();
  const auto& proj = frame.projection();
  const double s = 1.0 / frame.pixel_size();
  double u[kSpatialMax] = {}, v[kSpatialMax] = {};
  for (int k = 0; k < spatial && k < kSpatialMax; ++k) {
    u[k] = proj[0][k] * s;
    v[k] = -proj[1][k] * s;
  }
  const double u0 = -frame.window().xmin * s, v0 = frame.window().ymax * s;
  const auto& toward = frame.toward_viewer();
  Rng rng(seed, job);
  const Point start = ifs.start_point();
  double p[N], q[N];
  for (int c = 0; c < N; ++c) p[c] = start[c];
  std::uint32_t state = chain.start(rng);  // recurrent: the previous map
  auto step = [&] {
    state = chain.next(state, rng.next());
    const auto& m = maps[state];
    for (int r = 0; r < N; ++r) {
      double value = m.b[r];
      for (int c = 0; c < N; ++c) value += m.a[r][c] * p[c];
      q[r] = value;
    }
    for (int c = 0; c < N; ++c) p[c] = q[c];
  };
  for (std::uint64_t i = 0; i < skip; ++i) step();
  const std::size_t trash = std::size_t(frame.width()) * frame.height();
  const double w = frame.width(), h = frame.height();
  for (std::uint64_t i = 0; i < points; ++i) {
    step();
    double px = u0, py = v0;
    for (int k = 0; k < kSpatialMax; ++k) {
      px += u[k] * p[k];
      py += v[k] * p[k];
    }
    const bool inside = px >= 0.0 && px < w && py >= 0.0 && py < h;
    const std::size_t pixel = inside ? std::size_t(py) * frame.width() + std::size_t(px) : trash;
    acc.add(pixel, N > 3 || spatial < N ? p + spatial : nullptr);
    if constexpr (N >= 3)
      if (spatial == 3) acc.add_depth(pixel, toward[0] * p[0] + toward[1] * p[1] + toward[2] * p[2]);
  }
}

using ChaosJob = void (*)(const Ifs&, const Frame&, const MapChain&, std::uint64_t, std::uint64_t, std::uint64_t,
                          std::uint64_t, Accumulator&);

ChaosJob chaos_job_for(int dim) {
  static constexpr ChaosJob kJobs[] = {chaos_job_fixed<2>, chaos_job_fixed<3>, chaos_job_fixed<4>, chaos_job_fixed<5>,
                                       chaos_job_fixed<6>, chaos_job_fixed<7>, chaos_job_fixed<8>};
  return kJobs[dim - 2];
}

/// A 3D pixel's hits beside its largest depth: one cache line per point, not two.
struct HitDepth {
  std::uint32_t hits;
  float depth;
};

#ifdef IFSFORGE_CHAOS_AVX2

/// Up to 8 maps in pixel space (N = 2), or in pixel space plus depth towards the viewer
/// (N = 3), one coefficient per lane of each register.
template <int N>
struct PixelMaps {
  __m256 a[N * N], b[N];
  __m256i thresholds[7];  ///< cumulative probability - 1, 24-bit
  int count;
};

/// The frame's world-to-pixel map T: px = (u - xmin) sx, py = (ymax - v) sy, and in 3D
/// the third coordinate the depth towards the viewer (T's rows are orthogonal: invertible).
AffineMap to_pixel_space(const Frame& frame, int n) {
  const Window& win = frame.window();
  const double s = 1.0 / frame.pixel_size();
  if (n == 2) return AffineMap(2, {s, 0, 0, -s}, {-win.xmin * s, win.ymax * s});
  const auto& proj = frame.projection();
  const auto& toward = frame.toward_viewer();
  return AffineMap(3,
                   {proj[0][0] * s, proj[0][1] * s, proj[0][2] * s, -proj[1][0] * s, -proj[1][1] * s,
                    -proj[1][2] * s, toward[0], toward[1], toward[2]},
                   {-win.xmin * s, win.ymax * s, 0.0});
}

template <int N>
PixelMaps<N> pixel_maps(const Ifs& ifs, const Frame& frame) {
  // Each map conjugated by T: the lanes iterate in pixel coordinates.
  const AffineMap to_pixel = to_pixel_space(frame, N);
  const AffineMap from_pixel = *to_pixel.inverse();
  alignas(32) float a[N * N][8] = {}, b[N][8] = {};
  PixelMaps<N> m;
  m.count = static_cast<int>(ifs.size());
  double cumulative = 0.0;
  for (int i = 0; i < m.count; ++i) {
    const AffineMap w = to_pixel.compose(ifs.map(i)).compose(from_pixel);
    for (int r = 0; r < N; ++r) {
      for (int c = 0; c < N; ++c) a[r * N + c][i] = static_cast<float>(w.a(r, c));
      b[r][i] = static_cast<float>(w.b(r));
    }
    if (i + 1 < m.count) {
      cumulative += ifs.probabilities()[i];
      const int t = static_cast<int>(std::lround(cumulative * 16777216.0));
      m.thresholds[i] = _mm256_set1_epi32(t - 1);
    }
  }
  for (int k = 0; k < N * N; ++k) m.a[k] = _mm256_load_ps(a[k]);
  for (int r = 0; r < N; ++r) m.b[r] = _mm256_load_ps(b[r]);
  return m;
}

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

  void step(const PixelMaps<N>& m) {
    const __m256i u = _mm256_srli_epi32(next(), 8);  // top 24 bits
    __m256i index = _mm256_setzero_si256();
    for (int j = 0; j + 1 < m.count; ++j)
      index = _mm256_sub_epi32(index, _mm256_cmpgt_epi32(u, m.thresholds[j]));
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
    const __m256i inside = _mm256_and_si256(
        _mm256_and_si256(_mm256_cmpgt_epi32(ix, minus1), _mm256_cmpgt_epi32(width, ix)),
        _mm256_and_si256(_mm256_cmpgt_epi32(iy, minus1), _mm256_cmpgt_epi32(height, iy)));
    const __m256i slot = _mm256_add_epi32(_mm256_mullo_epi32(iy, width), ix);
    return _mm256_blendv_epi8(trash, slot, inside);
  }
};

constexpr int kGroups = 4;  // independent lane groups in flight, to hide FMA latency
constexpr std::uint64_t kLanes = 8 * kGroups;

/// One job of kGroups x 8 lanes: 8-bit hits into `low` (2D), each wrap of a byte adding 256
/// to the shared wide totals `carry`, or hits and the largest depth per pixel into `cells`
/// (3D); all with a trash slot at the end. The bytes keep a 1024^2 raster's counters at 1 MB,
/// inside the core's cache, where 32-bit ones (4 MB) spilled out of it: the scattered
/// increments ran at 640 M points/s, 1080 M/s at 256^2. A wrap comes once in 256 hits of a
/// pixel, so its atomic add (exact in any order) costs little and no per-worker carry array
/// is faulted in.
template <int N>
void chaos_job_avx2(const PixelMaps<N>& maps, const Frame& frame, const Point& start,
                    std::uint64_t points, std::uint64_t skip, std::uint64_t seed,
                    std::uint64_t job, std::uint8_t* low, std::uint64_t* carry, HitDepth* cells) {
  Lanes<N> lanes[kGroups];
  float origin[N];
  if constexpr (N == 2) {
    origin[0] = static_cast<float>((start[0] - frame.window().xmin) / frame.pixel_size());
    origin[1] = static_cast<float>((frame.window().ymax - start[1]) / frame.pixel_size());
  } else {
    double q[N];
    to_pixel_space(frame, N).apply(start.data(), q);
    for (int c = 0; c < N; ++c) origin[c] = static_cast<float>(q[c]);
  }
  for (int g = 0; g < kGroups; ++g) {
    alignas(32) std::uint32_t s[4][8];
    for (int lane = 0; lane < 8; ++lane) {
      Rng rng(seed, job * kLanes + g * 8 + lane);
      for (auto& word : s) {
        std::uint32_t v;
        do v = static_cast<std::uint32_t>(rng.next() >> 32);
        while (v == 0);  // xoshiro's state must not be all zero
        word[lane] = v;
      }
    }
    for (int c = 0; c < N; ++c) lanes[g].p[c] = _mm256_set1_ps(origin[c]);
    lanes[g].s0 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[0]));
    lanes[g].s1 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[1]));
    lanes[g].s2 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[2]));
    lanes[g].s3 = _mm256_load_si256(reinterpret_cast<const __m256i*>(s[3]));
  }
  for (std::uint64_t i = 0; i < skip; ++i)
    for (auto& l : lanes) l.step(maps);
  const __m256i width = _mm256_set1_epi32(frame.width());
  const __m256i height = _mm256_set1_epi32(frame.height());
  const __m256i trash = _mm256_set1_epi32(frame.width() * frame.height());
  alignas(32) std::uint32_t slot[kGroups][8];
  alignas(32) float depth[kGroups][8];
  for (std::uint64_t i = 0; i < points / kLanes; ++i) {
    for (int g = 0; g < kGroups; ++g) {
      lanes[g].step(maps);
      _mm256_store_si256(reinterpret_cast<__m256i*>(slot[g]), lanes[g].slots(width, height, trash));
      if constexpr (N == 3) _mm256_store_ps(depth[g], lanes[g].p[2]);
    }
    for (int g = 0; g < kGroups; ++g)
      for (int k = 0; k < 8; ++k) {
        if constexpr (N == 3) {
          HitDepth& cell = cells[slot[g][k]];
          ++cell.hits;
          cell.depth = std::max(cell.depth, depth[g][k]);
        } else {
          const std::uint32_t s = slot[g][k];
          if (++low[s] == 0) __atomic_fetch_add(carry + s, 256, __ATOMIC_RELAXED);
        }
      }
  }
}

#endif  // IFSFORGE_CHAOS_AVX2

/// What every job of one render shares: the frame, the point count and its cut into jobs.
struct ChaosSetup {
  Frame frame;
  JobPlan plan;
  std::vector<double> lo, hi;  // channel ranges
  bool simd = false;
};

ChaosSetup chaos_setup(const Ifs& ifs, const RenderOptions& options, int threads) {
  ifs.require_attractor();
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view);
  const std::uint64_t total = options.iterations ? options.iterations
                                                 : default_iterations(options.width, options.height,
                                                                      options.binary,
                                                                      options.points_per_pixel);
  std::vector<double> lo, hi;
  channel_ranges(ifs, lo, hi);
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
#ifdef IFSFORGE_CHAOS_AVX2
  // The lanes: a 2D system, or a purely spatial 3D one (its depth rides as the third lane).
  const bool simd = (ifs.dim() == 2 || (ifs.dim() == 3 && ifs.spatial_dims() == 3)) && ifs.size() <= 8 &&
                    !ifs.recurrent() && !ifs.polar();
#else
  const bool simd = false;
#endif
  // The lanes: one accumulator, and per worker 8-bit hits (in 3D, 32-bit hits beside float
  // depths).
  const double lane_bytes = simd ? threads * (ifs.dim() == 3 ? double(sizeof(HitDepth)) : 1.0) * pixels : 0.0;
  check_memory((simd ? 1 : threads) * Accumulator::bytes(frame.width(), frame.height(), false, lo.size()) + lane_bytes,
               "a " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                   " random-iteration image on " + std::to_string(threads) + " threads");
  return {frame, plan_jobs(total, simd ? 32 : 1), lo, hi, simd};
}

Accumulator empty_accumulator(const Ifs& ifs, const ChaosSetup& setup) {
  Accumulator acc(setup.frame.width(), setup.frame.height(), false, setup.lo, setup.hi);
  if (ifs.spatial_dims() == 3) acc.enable_depth();
  return acc;
}

/// Runs jobs [first, last) on `threads` threads into one accumulator (integer sums: the same
/// whatever the grouping of the jobs).
Accumulator chaos_accumulate(const Ifs& ifs, const RenderOptions& options, const ChaosSetup& setup,
                             std::uint64_t first, std::uint64_t last, int threads) {
  const Frame& frame = setup.frame;
  const JobPlan& plan = setup.plan;
#ifdef IFSFORGE_CHAOS_AVX2
  const bool simd = setup.simd;
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
#endif
  // The lanes count into narrow per-worker histograms flushed into one wide accumulator
  // (integer sums and a max: the order of flushes does not matter); the general path adds
  // into one accumulator per worker.
  std::vector<Accumulator> acc;
  for (int t = 0; t < (setup.simd ? 1 : threads); ++t) acc.push_back(empty_accumulator(ifs, setup));
  const MapChain chain(ifs);
  // Polar maps (3.3.3) take their own simple path: the affine kernels stay specialised.
  const ChaosJob scalar_job = ifs.polar() ? polar::chaos_job : chaos_job_for(ifs.dim());

#ifdef IFSFORGE_CHAOS_AVX2
  // Per worker: 8-bit hits (32-bit hits beside depths in 3D) flushed into the wide
  // accumulator: in 2D when the jobs are done (their wraps went there already), in 3D also
  // whenever a 32-bit counter could overflow.
  const bool depth = ifs.dim() == 3;
  std::vector<LargeVector<std::uint8_t>> lows(simd && !depth ? threads : 0);
  std::vector<LargeVector<HitDepth>> cells(simd && depth ? threads : 0);
  std::vector<std::uint64_t> pending(threads, 0);
  // Adds pixels [from, to) of a worker's narrow counters to the wide totals.
  auto add_lane = [&](int worker, std::size_t from, std::size_t to) {
    std::uint64_t* hits = acc[0].hits();
    if (depth) {
      const auto& c = cells[worker];
      for (std::size_t i = from; i < to; ++i) {
        hits[i] += c[i].hits;
        acc[0].add_depth(i, c[i].depth);
      }
    } else {
      const auto& low = lows[worker];
      for (std::size_t i = from; i < to; ++i) hits[i] += low[i];
    }
  };
  std::mutex flushing;
  auto flush = [&](int worker) {  // in 3D, before a 32-bit counter could overflow
    {
      std::lock_guard<std::mutex> lock(flushing);
      add_lane(worker, 0, cells[worker].size());
    }
    std::fill(cells[worker].begin(), cells[worker].end(), HitDepth{0, -std::numeric_limits<float>::infinity()});
    pending[worker] = 0;
  };
  PixelMaps<2> maps2{};
  PixelMaps<3> maps3{};
  if (simd && !depth) maps2 = pixel_maps<2>(ifs, frame);
  if (simd && depth) maps3 = pixel_maps<3>(ifs, frame);
  const Point start = ifs.start_point();
#endif

  parallel_jobs(
      last - first, threads,
      [&](std::size_t index, int worker) {
        const std::uint64_t job = first + index;
#ifdef IFSFORGE_CHAOS_AVX2
        if (simd) {
          if (depth && cells[worker].empty())
            assign_large(cells[worker], pixels + 1, HitDepth{0, -std::numeric_limits<float>::infinity()});
          if (!depth && lows[worker].empty()) assign_large(lows[worker], pixels + 1, std::uint8_t(0));
          // A 32-bit counter could overflow if one pixel took every point: flush first.
          if (depth && pending[worker] + plan.points_per_job >= 0xFFFFFFFFull) flush(worker);
          if (depth)
            chaos_job_avx2(maps3, frame, start, plan.points_per_job, options.skip, options.seed, job, nullptr, nullptr,
                           cells[worker].data());
          else
            chaos_job_avx2(maps2, frame, start, plan.points_per_job, options.skip, options.seed, job,
                           lows[worker].data(), acc[0].hits(), nullptr);
          pending[worker] += plan.points_per_job;
          return;
        }
#endif
        scalar_job(ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, acc[worker]);
      },
      options.progress);

#ifdef IFSFORGE_CHAOS_AVX2
  // The workers' counters into the totals in pixel bands on every core (sums and maxima: the
  // same bytes for any split).
  if (simd) {
    constexpr std::size_t kBand = 1 << 16;
    parallel_jobs((pixels + 1 + kBand - 1) / kBand, threads, [&](std::size_t band, int) {
      const std::size_t from = band * kBand, to = std::min(pixels + 1, from + kBand);
      for (int t = 0; t < threads; ++t)
        if (!(depth ? cells[t].empty() : lows[t].empty())) add_lane(t, from, to);
    });
  }
#endif
  for (std::size_t t = 1; t < acc.size(); ++t) acc[0].merge(acc[t]);
  return std::move(acc[0]);
}

}  // namespace

Capabilities ChaosGame::capabilities() const {
  // Random iteration follows the walker (transitions), applies polar maps and converges for
  // average-contractive systems; a condensation set it does not draw.
  using C = Capabilities;
  return {C::Recurrent | C::Polar | C::AverageContractive | C::Overlapping | C::Plane | C::Space};
}

Raster ChaosGame::draw(const Ifs& ifs, const RenderOptions& options) const {
  const int threads = options.distribute ? 1 : resolve_threads(options.threads);
  const ChaosSetup setup = chaos_setup(ifs, options, threads);
  // One accumulator either way (an 8 MB one at 1024^2: building a spare cost its page faults).
  Accumulator acc = options.distribute ? empty_accumulator(ifs, setup)
                                       : chaos_accumulate(ifs, options, setup, 0, setup.plan.jobs, threads);
  if (options.distribute)
    for (std::string_view bytes : options.distribute(0, setup.plan.jobs, options.depth)) acc.merge_encoded(bytes);
  Raster raster;
  describe_channels(ifs, raster);
  acc.finish(raster, threads);
  raster.pixel_size = setup.frame.pixel_size();
  raster.points = setup.plan.jobs * setup.plan.points_per_job;
  return raster;
}

std::string ChaosGame::draw_jobs(const Ifs& ifs, const RenderOptions& options, std::uint64_t first,
                                 std::uint64_t last) const {
  const int threads = resolve_threads(options.threads);
  const ChaosSetup setup = chaos_setup(ifs, options, threads);
  last = std::min(last, setup.plan.jobs);
  if (first >= last) return empty_accumulator(ifs, setup).encode();
  const int used = static_cast<int>(std::min<std::uint64_t>(threads, last - first));
  return chaos_accumulate(ifs, options, setup, first, last, used).encode();
}

}  // namespace ifsforge
