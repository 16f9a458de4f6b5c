#include "ifsforge/render/chaos_game.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/fixed_maps.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "chaos_chains_plan.h"
#include "chaos_hits.h"
#include "chaos_lanes.h"
#include "chaos_sinks.h"
#include "chaos_tiles.h"
#include "polar_render.h"

namespace ifsforge {
namespace {

using lanes::HitDepth;
using sinks::AccumulatorSink;
using sinks::ChannelSink;
using sinks::NarrowSink;

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

using ChaosJob = void (*)(const Ifs&, const Frame&, const MapChain&, std::uint64_t, std::uint64_t, std::uint64_t,
                          std::uint64_t, Accumulator&);

template <int N>
void accumulator_job(const Ifs& ifs, const Frame& frame, const MapChain& chain, std::uint64_t points,
                     std::uint64_t skip, std::uint64_t seed, std::uint64_t job, Accumulator& acc) {
  chaos_job_fixed<N>(ifs, frame, chain, points, skip, seed, job, AccumulatorSink{acc});
}

using ChannelJob = void (*)(const Ifs&, const Frame&, const MapChain&, std::uint64_t, std::uint64_t, std::uint64_t,
                            std::uint64_t, const ChannelSink&);

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

/// What every job of one render shares: the frame, the point count and its cut into jobs.
struct ChaosSetup {
  Frame frame;
  JobPlan plan;
  std::vector<double> lo, hi;  // channel ranges
  bool simd = false;    // the lane kernels run the jobs
  bool narrow = false;  // the jobs count into narrow per-worker counters (every lane job does)
};

/// Whether a render's 2D lane counts go through tiles (chaos_tiles.h).
bool tiled_counts(bool simd, bool depth, std::size_t pixels) {
  return simd && !depth && pixels >= lanes::tiled_from_pixels() && lanes::lane_tiles();
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

/// Runs jobs [first, last) on `threads` threads into one accumulator (integer sums: the same
/// whatever the grouping of the jobs); with `direct` (where lane_hits), into it instead, and
/// no accumulator.
std::optional<Accumulator> chaos_accumulate(const Ifs& ifs, const RenderOptions& options, const ChaosSetup& setup,
                                            std::uint64_t first, std::uint64_t last, int threads,
                                            sinks::LaneHits* direct = nullptr) {
  const Frame& frame = setup.frame;
  const JobPlan& plan = setup.plan;
  const bool simd = setup.simd, narrow = setup.narrow;
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
  // Narrow per-worker counters (the lanes, and the general path where setup.narrow) are flushed
  // into one wide accumulator (integer sums and a max: the order of flushes does not matter);
  // otherwise each worker adds into an accumulator of its own.
  std::vector<Accumulator> acc;
  for (int t = 0; t < (direct ? 0 : narrow ? 1 : threads); ++t) acc.push_back(empty_accumulator(ifs, setup));
  const MapChain chain(ifs);
  // Polar maps (3.3.3) take their own simple path: the affine kernels stay specialised.
  const ChaosJob scalar_job = ifs.polar() ? polar::chaos_job : chaos_job_for(ifs.dim());

  // Per worker: 8-bit hits (32-bit hits beside depths in 3D; 32-bit hits and channel sums in
  // 2D with channels) flushed into the wide accumulator: when the jobs are done (the wraps went
  // there already), and also whenever a 32-bit hit counter could overflow.
  const bool depth = ifs.spatial_dims() == 3;
  const int channels = static_cast<int>(setup.lo.size()), stride = channels + 1;
  const bool packed = narrow && channels > 0;
  std::vector<ZeroedVector<std::uint8_t>> lows(narrow && !depth && !packed ? threads : 0);
  std::vector<LargeVector<HitDepth>> cells(narrow && depth ? threads : 0);
  std::vector<LargeVector<std::uint32_t>> records(packed ? threads : 0);
  std::vector<std::uint64_t> pending(threads, 0);
  // Adds pixels [from, to) of a worker's narrow counters to the wide totals.
  auto add_lane = [&](int worker, std::size_t from, std::size_t to) {
    std::uint64_t* hits = acc[0].hits();
    if (packed) {
      const std::uint32_t* r = records[worker].data();
      std::uint64_t* sums = acc[0].sums();
      for (std::size_t i = from; i < to; ++i) {
        hits[i] += r[i * stride];
        for (int c = 0; c < channels; ++c) sums[i * channels + c] += r[i * stride + 1 + c];
      }
    } else if (depth) {
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
  auto flush = [&](int worker) {  // 32-bit hits: before one could overflow
    {
      std::lock_guard<std::mutex> lock(flushing);
      add_lane(worker, 0, pixels + 1);
    }
    if (packed)
      std::fill(records[worker].begin(), records[worker].end(), 0u);
    else
      std::fill(cells[worker].begin(), cells[worker].end(), HitDepth{0, -std::numeric_limits<float>::infinity()});
    pending[worker] = 0;
  };
  // Large 2D images: each worker bins its slots by tile and counts them tile by tile.
  const bool tiled = tiled_counts(simd, depth, pixels);
  std::vector<std::unique_ptr<lanes::TiledCounter>> tiles(tiled ? threads : 0);
  std::vector<std::vector<std::uint32_t>> batches(tiled ? threads : 0);
  const int n = depth ? 3 : 2;
  const lanes::Maps maps = simd ? pixel_maps(ifs, frame, n) : lanes::Maps{};
  const lanes::Kernel kernel = simd ? lanes::lane_kernel(n) : nullptr;
  const Point start = ifs.start_point();
  // The general path's affine jobs run side by side in the chain lanes, a task of up to 8 jobs
  // (each job's chain and points unchanged: the same bytes); else one job per task. A task of
  // one job takes the one-job loop: lanes that carry a single chain cost more than it.
  const bool chained = !simd && !ifs.polar() && chains::enabled() && pixels < (std::size_t(1) << 31);
  const std::unique_ptr<chains::Plan> chain_plan = chained ? std::make_unique<chains::Plan>(ifs, frame, chain, acc[0]) : nullptr;
  const std::uint64_t per_task = chained ? chains::jobs_per_task(last - first, threads) : 1;

  parallel_jobs(
      (last - first + per_task - 1) / per_task, threads,
      [&](std::size_t index, int worker) {
        const std::uint64_t job = first + index * per_task;
        const int count = static_cast<int>(std::min(per_task, last - job));
        const bool side_by_side = chained && count > 1;
        auto run_chains = [&](const auto& sink) {
          chain_plan->run(job, count, plan.points_per_job, options.skip, options.seed, sink);
        };
        if (!narrow) {
          if (side_by_side)
            run_chains(AccumulatorSink{acc[worker]});
          else
            scalar_job(ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, acc[worker]);
          return;
        }
        if (depth && cells[worker].empty())
          assign_large(cells[worker], pixels + 1, HitDepth{0, -std::numeric_limits<float>::infinity()});
        if (!depth && !packed && lows[worker].empty()) zeroed_large(lows[worker], pixels + 1);
        if (packed && records[worker].empty()) assign_large(records[worker], (pixels + 1) * stride, 0u);
        // A 32-bit counter could overflow if one pixel took every point: flush first.
        if ((depth || packed) && pending[worker] + count * plan.points_per_job >= 0xFFFFFFFFull) flush(worker);
        pending[worker] += count * plan.points_per_job;
        if (packed) {
          const ChannelSink sink{records[worker].data(), acc[0].sums(), &acc[0], channels};
          if (side_by_side)
            run_chains(sink);
          else
            channel_job_for(ifs.dim())(ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, sink);
          return;
        }
        const NarrowSink sink{depth ? nullptr : lows[worker].data(), direct ? direct->carry.data() : acc[0].hits(),
                              depth ? cells[worker].data() : nullptr};
        if (side_by_side) {
          run_chains(sink);
          return;
        }
        if (!simd) {
          const int dim = ifs.dim();
          (dim == 2 ? chaos_job_fixed<2, NarrowSink> : chaos_job_fixed<3, NarrowSink>)(
              ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, sink);
          return;
        }
        lanes::Job lane = lane_job(frame, n, start, plan.points_per_job, options.skip, options.seed, job);
        lane.low = sink.low;
        lane.carry = sink.carry;
        lane.cells = sink.cells;
        if (tiled) {
          if (!tiles[worker]) {
            tiles[worker] = std::make_unique<lanes::TiledCounter>(pixels + 1, lane.low);
            batches[worker].resize(lanes::kTileBatch);
          }
          lane.batch = batches[worker].data();
          lane.batch_size = lanes::kTileBatch;
          lane.flush = lanes::TiledCounter::flush;
          lane.sink = tiles[worker].get();
        }
        kernel(maps, lane);
      },
      options.progress);
  // What the bins still hold, each worker's on a core of its own.
  if (tiled)
    parallel_jobs(tiles.size(), threads, [&](std::size_t t, int) {
      if (tiles[t]) tiles[t]->drain();
    });

  // The wraps the tiles listed: 256 hits each.
  for (auto& counter : tiles) {
    if (!counter) continue;
    std::vector<std::vector<std::uint16_t>> wraps = counter->take_wraps();
    if (direct) {
      direct->wraps.push_back(std::move(wraps));
      continue;
    }
    for (std::size_t t = 0; t < wraps.size(); ++t)
      for (std::uint16_t offset : wraps[t]) acc[0].hits()[(t << lanes::kTileShift) + offset] += 256;
  }
  if (direct) {  // the sums are made as the raster's density
    direct->lows = std::move(lows);
    return std::nullopt;
  }
  // The workers' counters into the totals in pixel bands on every core (sums and maxima: the
  // same bytes for any split).
  if (narrow) {
    constexpr std::size_t kBand = 1 << 16;
    parallel_jobs((pixels + 1 + kBand - 1) / kBand, threads, [&](std::size_t band, int) {
      const std::size_t from = band * kBand, to = std::min(pixels + 1, from + kBand);
      for (int t = 0; t < threads; ++t)
        if (!(packed ? records[t].empty() : depth ? cells[t].empty() : lows[t].empty())) add_lane(t, from, to);
    });
  }
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
  Raster raster;
  describe_channels(ifs, raster);
  const Frame& frame = setup.frame;
  if (!options.distribute && lane_hits(ifs, setup)) {
    const std::size_t pixels = std::size_t(frame.width()) * frame.height();
    sinks::LaneHits hits(pixels + 1, !tiled_counts(setup.simd, false, pixels));
    chaos_accumulate(ifs, options, setup, 0, setup.plan.jobs, threads, &hits);
    hits.finish(raster, frame.width(), frame.height(), threads);
  } else {
    // One accumulator either way (an 8 MB one at 1024^2: building a spare cost its page faults).
    Accumulator acc = options.distribute ? empty_accumulator(ifs, setup)
                                         : *chaos_accumulate(ifs, options, setup, 0, setup.plan.jobs, threads);
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
  return chaos_accumulate(ifs, options, setup, first, last, used)->encode();
}

}  // namespace ifsforge
