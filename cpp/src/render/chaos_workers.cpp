#include "chaos_workers.h"

#include <algorithm>
#include <limits>

#include "ifsforge/core/parallel.h"
#include "chaos_chains_plan.h"

namespace ifsforge::workers {

using lanes::HitDepth;
using sinks::AccumulatorSink;
using sinks::ChannelSink;
using sinks::NarrowSink;

bool tiled_counts(bool simd, bool depth, std::size_t pixels) {
  return simd && !depth && pixels >= lanes::tiled_from_pixels() && lanes::lane_tiles();
}

WorkerCounters::WorkerCounters(const Ifs& ifs, const ChaosSetup& setup, int threads, Accumulator* wide,
                               std::uint64_t* carry)
    : wide_(wide),
      carry_(carry),
      threads_(threads),
      pixels_(std::size_t(setup.frame.width()) * setup.frame.height()),
      narrow_(setup.narrow),
      depth_(ifs.spatial_dims() == 3),
      packed_(setup.narrow && !setup.lo.empty()),
      tiled_(tiled_counts(setup.simd, depth_, pixels_)),
      channels_(static_cast<int>(setup.lo.size())),
      stride_(channels_ + 1),
      lows_(narrow_ && !depth_ && !packed_ ? threads : 0),
      cells_(narrow_ && depth_ ? threads : 0),
      records_(packed_ ? threads : 0),
      pending_(threads, 0),
      tiles_(tiled_ ? threads : 0),
      batches_(tiled_ ? threads : 0) {}

WorkerCounters::WorkerCounters(const Ifs& ifs, const ChaosSetup& setup, int threads, Accumulator& wide)
    : WorkerCounters(ifs, setup, threads, &wide, wide.hits()) {}

WorkerCounters::WorkerCounters(const Ifs& ifs, const ChaosSetup& setup, int threads, sinks::LaneHits& hits)
    : WorkerCounters(ifs, setup, threads, nullptr, hits.carry.data()) {}

// Adds pixels [from, to) of a worker's narrow counters to the wide totals.
void WorkerCounters::add_lane(int worker, std::size_t from, std::size_t to) {
  std::uint64_t* hits = wide_->hits();
  if (packed_) {
    const std::uint32_t* r = records_[worker].data();
    std::uint64_t* sums = wide_->sums();
    for (std::size_t i = from; i < to; ++i) {
      hits[i] += r[i * stride_];
      for (int c = 0; c < channels_; ++c) sums[i * channels_ + c] += r[i * stride_ + 1 + c];
    }
  } else if (depth_) {
    const auto& c = cells_[worker];
    for (std::size_t i = from; i < to; ++i) {
      hits[i] += c[i].hits;
      wide_->add_depth(i, c[i].depth);
    }
  } else {
    const auto& low = lows_[worker];
    for (std::size_t i = from; i < to; ++i) hits[i] += low[i];
  }
}

void WorkerCounters::flush(int worker) {  // 32-bit hits: before one could overflow
  {
    std::lock_guard<std::mutex> lock(flushing_);
    add_lane(worker, 0, pixels_ + 1);
  }
  if (packed_)
    std::fill(records_[worker].begin(), records_[worker].end(), 0u);
  else
    std::fill(cells_[worker].begin(), cells_[worker].end(), HitDepth{0, -std::numeric_limits<float>::infinity()});
  pending_[worker] = 0;
}

void WorkerCounters::prepare(int worker, std::uint64_t points) {
  if (depth_ && cells_[worker].empty())
    assign_large(cells_[worker], pixels_ + 1, HitDepth{0, -std::numeric_limits<float>::infinity()});
  if (!depth_ && !packed_ && lows_[worker].empty()) zeroed_large(lows_[worker], pixels_ + 1);
  if (packed_ && records_[worker].empty()) assign_large(records_[worker], (pixels_ + 1) * stride_, 0u);
  // A 32-bit counter could overflow if one pixel took every point: flush first.
  if ((depth_ || packed_) && pending_[worker] + points >= 0xFFFFFFFFull) flush(worker);
  pending_[worker] += points;
}

ChannelSink WorkerCounters::channel_sink(int worker) {
  return {records_[worker].data(), wide_->sums(), wide_, channels_};
}

NarrowSink WorkerCounters::narrow_sink(int worker) {
  return {depth_ ? nullptr : lows_[worker].data(), carry_, depth_ ? cells_[worker].data() : nullptr};
}

void WorkerCounters::bin(int worker, lanes::Job& lane) {
  if (!tiled_) return;
  if (!tiles_[worker]) {
    tiles_[worker] = std::make_unique<lanes::TiledCounter>(pixels_ + 1, lane.low);
    batches_[worker].resize(lanes::kTileBatch);
  }
  lane.batch = batches_[worker].data();
  lane.batch_size = lanes::kTileBatch;
  lane.flush = lanes::TiledCounter::flush;
  lane.sink = tiles_[worker].get();
}

void WorkerCounters::drain() {
  if (tiled_)
    parallel_jobs(tiles_.size(), threads_, [&](std::size_t t, int) {
      if (tiles_[t]) tiles_[t]->drain();
    });
}

void WorkerCounters::total() {
  // The wraps the tiles listed: 256 hits each.
  for (auto& counter : tiles_) {
    if (!counter) continue;
    std::vector<std::vector<std::uint16_t>> wraps = counter->take_wraps();
    for (std::size_t t = 0; t < wraps.size(); ++t)
      for (std::uint16_t offset : wraps[t]) wide_->hits()[(t << lanes::kTileShift) + offset] += 256;
  }
  // The workers' counters into the totals in pixel bands on every core (sums and maxima: the
  // same bytes for any split).
  if (narrow_) {
    constexpr std::size_t kBand = 1 << 16;
    parallel_jobs((pixels_ + 1 + kBand - 1) / kBand, threads_, [&](std::size_t band, int) {
      const std::size_t from = band * kBand, to = std::min(pixels_ + 1, from + kBand);
      for (int t = 0; t < threads_; ++t)
        if (!(packed_ ? records_[t].empty() : depth_ ? cells_[t].empty() : lows_[t].empty())) add_lane(t, from, to);
    });
  }
}

void WorkerCounters::hand_to(sinks::LaneHits& hits) {
  for (auto& counter : tiles_)
    if (counter) hits.wraps.push_back(counter->take_wraps());
  hits.lows = std::move(lows_);  // the sums are made as the raster's density
}

void run_jobs(const Ifs& ifs, const RenderOptions& options, const ChaosSetup& setup, const Jobs& jobs,
              std::uint64_t first, std::uint64_t last, int threads, std::vector<Accumulator>& acc,
              WorkerCounters& counters) {
  const Frame& frame = setup.frame;
  const JobPlan& plan = setup.plan;
  const bool simd = setup.simd, narrow = setup.narrow;
  const std::size_t pixels = std::size_t(frame.width()) * frame.height();
  const MapChain chain(ifs);
  const int n = ifs.spatial_dims() == 3 ? 3 : 2;
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
            jobs.scalar(ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, acc[worker]);
          return;
        }
        counters.prepare(worker, count * plan.points_per_job);
        if (counters.packed()) {
          const ChannelSink sink = counters.channel_sink(worker);
          if (side_by_side)
            run_chains(sink);
          else
            jobs.channel(ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, sink);
          return;
        }
        const NarrowSink sink = counters.narrow_sink(worker);
        if (side_by_side) {
          run_chains(sink);
          return;
        }
        if (!simd) {
          jobs.narrow(ifs, frame, chain, plan.points_per_job, options.skip, options.seed, job, sink);
          return;
        }
        lanes::Job lane = jobs.lane(frame, n, start, plan.points_per_job, options.skip, options.seed, job);
        lane.low = sink.low;
        lane.carry = sink.carry;
        lane.cells = sink.cells;
        counters.bin(worker, lane);
        jobs.kernel(jobs.maps, lane);
      },
      options.progress);
  counters.drain();
}

}  // namespace ifsforge::workers
