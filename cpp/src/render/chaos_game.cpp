#include "ifsforge/render/chaos_game.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/fixed_maps.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "chaos_hits.h"
#include "chaos_lanes.h"
#include "chaos_sinks.h"
#include "chaos_tiles.h"
#include "chaos_workers.h"
#include "polar_render.h"

namespace ifsforge {
namespace {

using lanes::HitDepth;
using sinks::AccumulatorSink;
using sinks::ChannelSink;
using sinks::NarrowSink;
using workers::ChannelJob;
using workers::ChaosJob;
using workers::ChaosSetup;
using workers::JobPlan;
using workers::tiled_counts;

constexpr std::uint64_t kPointsPerJob = 1u << 22;

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
template <int N, class Sink>
void chaos_job_fixed(const Ifs& ifs, const Frame& frame, const MapChain& chain, std::uint64_t points,
                     std::uint64_t skip, std::uint64_t seed, std::uint64_t job, const Sink& sink) {
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
  // Each point is added kAhead points after its counters were prefetched (integer sums and a
  // maximum: the order of the adds does not change the bytes).
  constexpr std::uint64_t kAhead = 16;
  struct Pending {
    std::size_t pixel;
    double p[N];
    double depth;
  } pending[kAhead];
  auto add = [&](const Pending& point) {
    sink.add(point.pixel, N > 3 || spatial < N ? point.p + spatial : nullptr, N >= 3 && spatial == 3, point.depth);
  };
  for (std::uint64_t i = 0; i < points; ++i) {
    step();
    double px = u0, py = v0;
    for (int k = 0; k < kSpatialMax; ++k) {
      px += u[k] * p[k];
      py += v[k] * p[k];
    }
    const bool inside = px >= 0.0 && px < w && py >= 0.0 && py < h;
    Pending& slot = pending[i % kAhead];
    if (i >= kAhead) add(slot);
    slot.pixel = inside ? std::size_t(py) * frame.width() + std::size_t(px) : trash;
    for (int c = 0; c < N; ++c) slot.p[c] = p[c];
    slot.depth = N >= 3 ? toward[0] * p[0] + toward[1] * p[1] + toward[2] * p[2] : 0.0;
    sink.prefetch(slot.pixel);
  }
  for (std::uint64_t i = points > kAhead ? points - kAhead : 0; i < points; ++i) add(pending[i % kAhead]);
}

template <int N>
void accumulator_job(const Ifs& ifs, const Frame& frame, const MapChain& chain, std::uint64_t points,
                     std::uint64_t skip, std::uint64_t seed, std::uint64_t job, Accumulator& acc) {
  chaos_job_fixed<N>(ifs, frame, chain, points, skip, seed, job, AccumulatorSink{acc});
}

ChannelJob channel_job_for(int dim) {
  static constexpr ChannelJob kJobs[] = {chaos_job_fixed<3, ChannelSink>, chaos_job_fixed<4, ChannelSink>,
                                         chaos_job_fixed<5, ChannelSink>, chaos_job_fixed<6, ChannelSink>,
                                         chaos_job_fixed<7, ChannelSink>, chaos_job_fixed<8, ChannelSink>};
  return kJobs[dim - 3];
}

ChaosJob chaos_job_for(int dim) {
  static constexpr ChaosJob kJobs[] = {accumulator_job<2>, accumulator_job<3>, accumulator_job<4>,
                                       accumulator_job<5>, accumulator_job<6>, accumulator_job<7>,
                                       accumulator_job<8>};
  return kJobs[dim - 2];
}

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

/// The lanes' maps: up to 8 maps in pixel space (N = 2) or pixel space plus depth (N = 3),
/// each conjugated by T so that the lanes iterate in pixel coordinates.
lanes::Maps pixel_maps(const Ifs& ifs, const Frame& frame, int n) {
  const AffineMap to_pixel = to_pixel_space(frame, n);
  const AffineMap from_pixel = *to_pixel.inverse();
  lanes::Maps m{};
  m.count = static_cast<int>(ifs.size());
  double cumulative = 0.0;
  for (int i = 0; i < m.count; ++i) {
    const AffineMap w = to_pixel.compose(ifs.map(i)).compose(from_pixel);
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) m.a[r * n + c][i] = static_cast<float>(w.a(r, c));
      m.b[r][i] = static_cast<float>(w.b(r));
    }
    if (i + 1 < m.count) {
      cumulative += ifs.probabilities()[i];
      m.thresholds[i] = static_cast<int>(std::lround(cumulative * 16777216.0)) - 1;
    }
  }
  return m;
}

/// Job `job`'s lanes: the start point in pixel space and one xoshiro128+ state per lane, drawn
/// from the job's own streams (the image depends on the seed and the job, not on the kernel).
lanes::Job lane_job(const Frame& frame, int n, const Point& start, std::uint64_t points, std::uint64_t skip,
                    std::uint64_t seed, std::uint64_t job) {
  lanes::Job j{};
  if (n == 2) {
    j.origin[0] = static_cast<float>((start[0] - frame.window().xmin) / frame.pixel_size());
    j.origin[1] = static_cast<float>((frame.window().ymax - start[1]) / frame.pixel_size());
  } else {
    double q[3];
    to_pixel_space(frame, n).apply(start.data(), q);
    for (int c = 0; c < n; ++c) j.origin[c] = static_cast<float>(q[c]);
  }
  for (int g = 0; g < lanes::kGroups; ++g)
    for (int lane = 0; lane < lanes::kWidth; ++lane) {
      Rng rng(seed, job * lanes::kLanes + g * lanes::kWidth + lane);
      for (auto& word : j.state[g]) {
        std::uint32_t v;
        do v = static_cast<std::uint32_t>(rng.next() >> 32);
        while (v == 0);  // xoshiro's state must not be all zero
        word[lane] = v;
      }
    }
  j.points = points;
  j.skip = skip;
  j.width = frame.width();
  j.height = frame.height();
  return j;
}

ChaosSetup chaos_setup(const Ifs& ifs, const RenderOptions& options, int threads) {
  ifs.require_attractor();
  const Frame frame = Frame::fit(ifs, options.width, options.height, options.window, options.view, Frame::kMargin, threads);
  const std::uint64_t total = options.iterations ? options.iterations
                                                 : default_iterations(options.width, options.height,
                                                                      options.binary,
                                                                      options.points_per_pixel);
  std::vector<double> lo, hi;
  channel_ranges(ifs, lo, hi);
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
  // The lanes: a 2D system, or a purely spatial 3D one (its depth rides as the third lane).
  const bool simd = (ifs.dim() == 2 || (ifs.dim() == 3 && ifs.spatial_dims() == 3)) &&
                    ifs.size() <= std::size_t(lanes::kWidth) && !ifs.recurrent() && !ifs.polar();
  // Narrow counters: any purely spatial 2D or 3D system (the general path's too: more maps,
  // recurrent) or 2D one with channels; one accumulator, and per worker 8-bit hits (in 3D,
  // 32-bit hits beside float depths; with channels, 32-bit hits and sums). Polar maps and 3D
  // systems with channels add into an accumulator per worker.
  const int spatial = ifs.spatial_dims(), channels = ifs.dim() - spatial;
  const bool narrow =
      simd || (!ifs.polar() && lanes::narrow_counters() && (spatial == 2 || (spatial == 3 && ifs.dim() == 3)));
  const double cell_bytes = channels ? 4.0 * (channels + 1) : spatial == 3 ? double(sizeof(HitDepth)) : 1.0;
  const double bin_bytes = tiled_counts(simd, spatial == 3, pixels) ? double(lanes::TiledCounter::bytes(pixels + 1)) : 0.0;
  const double lane_bytes = narrow ? threads * (cell_bytes * pixels + bin_bytes) : 0.0;
  check_memory((narrow ? 1 : threads) * Accumulator::bytes(frame.width(), frame.height(), false, lo.size()) + lane_bytes,
               "a " + std::to_string(frame.width()) + "x" + std::to_string(frame.height()) +
                   " random-iteration image on " + std::to_string(threads) + " threads");
  return {frame, plan_jobs(total, simd ? lanes::kLanes : 1), lo, hi, simd, narrow};
}

Accumulator empty_accumulator(const Ifs& ifs, const ChaosSetup& setup) {
  Accumulator acc(setup.frame.width(), setup.frame.height(), false, setup.lo, setup.hi);
  if (ifs.spatial_dims() == 3) acc.enable_depth();
  return acc;
}

/// Whether a render's counts can skip the accumulator (chaos_hits.h): 2D lanes, 8-bit counters.
bool lane_hits(const Ifs& ifs, const ChaosSetup& setup) { return setup.simd && ifs.spatial_dims() == 2; }

/// A render's job functions (chaos_workers.h runs them).
workers::Jobs chaos_jobs(const Ifs& ifs, const ChaosSetup& setup) {
  const int n = ifs.spatial_dims() == 3 ? 3 : 2;
  const bool packed = setup.narrow && !setup.lo.empty();
  // Polar maps (3.3.3) take their own simple path: the affine kernels stay specialised.
  return {ifs.polar() ? polar::chaos_job : chaos_job_for(ifs.dim()),
          packed ? channel_job_for(ifs.dim()) : nullptr,
          ifs.dim() == 2 ? chaos_job_fixed<2, NarrowSink> : chaos_job_fixed<3, NarrowSink>,
          setup.simd ? pixel_maps(ifs, setup.frame, n) : lanes::Maps{},
          setup.simd ? lanes::lane_kernel(n) : nullptr,
          lane_job};
}

/// Runs jobs [first, last) on `threads` threads into one accumulator (integer sums: the same
/// whatever the grouping of the jobs).
Accumulator chaos_accumulate(const Ifs& ifs, const RenderOptions& options, const ChaosSetup& setup,
                             std::uint64_t first, std::uint64_t last, int threads) {
  // Narrow per-worker counters (the lanes, and the general path where setup.narrow) are flushed
  // into one wide accumulator (integer sums and a max: the order of flushes does not matter);
  // otherwise each worker adds into an accumulator of its own.
  std::vector<Accumulator> acc;
  for (int t = 0; t < (setup.narrow ? 1 : threads); ++t) acc.push_back(empty_accumulator(ifs, setup));
  workers::WorkerCounters counters(ifs, setup, threads, acc[0]);
  workers::run_jobs(ifs, options, setup, chaos_jobs(ifs, setup), first, last, threads, acc, counters);
  counters.total();
  for (std::size_t t = 1; t < acc.size(); ++t) acc[0].merge(acc[t]);
  return std::move(acc[0]);
}

/// Runs a 2D lane render's jobs (where lane_hits) into `hits`, and no accumulator.
void chaos_lane_hits(const Ifs& ifs, const RenderOptions& options, const ChaosSetup& setup, int threads,
                     sinks::LaneHits& hits) {
  std::vector<Accumulator> none;
  workers::WorkerCounters counters(ifs, setup, threads, hits);
  workers::run_jobs(ifs, options, setup, chaos_jobs(ifs, setup), 0, setup.plan.jobs, threads, none, counters);
  counters.hand_to(hits);
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
  Raster raster;
  describe_channels(ifs, raster);
  const Frame& frame = setup.frame;
  if (!options.distribute && lane_hits(ifs, setup)) {
    const std::size_t pixels = std::size_t(frame.width()) * frame.height();
    sinks::LaneHits hits(pixels + 1, !tiled_counts(setup.simd, false, pixels));
    chaos_lane_hits(ifs, options, setup, threads, hits);
    hits.finish(raster, frame.width(), frame.height(), threads);
  } else {
    // One accumulator either way (an 8 MB one at 1024^2: building a spare cost its page faults).
    Accumulator acc = options.distribute ? empty_accumulator(ifs, setup)
                                         : chaos_accumulate(ifs, options, setup, 0, setup.plan.jobs, threads);
    if (options.distribute)
      for (std::string_view bytes : options.distribute(0, setup.plan.jobs, options.depth)) acc.merge_encoded(bytes);
    acc.finish(raster, threads);
  }
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
