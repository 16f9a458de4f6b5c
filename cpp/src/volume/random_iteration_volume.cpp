#include "ifsforge/volume/random_iteration_volume.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/fixed_maps.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/volume/volume_jobs.h"
#include "voxel_bins.h"
#include "voxel_chains_plan.h"
#include "voxel_table.h"

namespace ifsforge {
namespace {

constexpr std::uint64_t kPointsPerJob = std::uint64_t(1) << 20;
constexpr std::uint64_t kSkip = 100;  // min_no_of_iterations of 5.1.1
constexpr std::uint64_t kMaxAutoPoints = std::uint64_t(1) << 34;

/// One job of the chaos game in N dimensions (a template parameter, so the map unrolls); the
/// maps come from the walker's chain (model/orbit.h), a recurrent system's transitions followed.
/// The one-job loop: where the CPU has vector lanes, the chain lanes (voxel_chains.h) draw the
/// same points, several jobs at once.
template <int N>
void chaos_job(const Ifs& ifs, const MapChain& chain, const VoxelGrid& grid,
               const ChannelQuantizer& quantizer, std::uint64_t points, std::uint64_t seed,
               std::uint64_t job, VoxelTable& table, VoxelBins& bins) {
  const auto maps = fixed_maps<N>(ifs);
  Rng rng(seed, job);
  const Point start = ifs.start_point();
  double p[N], q[N];
  for (int c = 0; c < N; ++c) p[c] = start[c];
  std::uint32_t state = chain.start(rng);
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
  for (std::uint64_t i = 0; i < kSkip; ++i) step();
  // Points go in batches: every key of a batch is computed and its slot prefetched before
  // the first add, so the table's cache misses overlap instead of stalling one by one; or, into
  // a large table, through bins by region (voxel_bins.h).
  const bool binned = bins.start<N - 3>(table);
  constexpr int kBatch = 16;
  std::uint64_t keys[kBatch], values[kBatch][kMaxDim] = {};
  for (std::uint64_t done = 0; done < points;) {
    const int batch = static_cast<int>(std::min<std::uint64_t>(kBatch, points - done));
    int kept = 0;
    for (int b = 0; b < batch; ++b) {
      step();
      if (!grid.voxel_of(p, keys[kept])) {
        if (!std::isfinite(p[0] + p[1] + p[2]))
          throw DivergentSystemError("system '" + ifs.name() + "' escapes to infinity under iteration");
        continue;
      }
      for (int c = 3; c < N; ++c) values[kept][c - 3] = quantizer.quantize(c - 3, p[c]);
      if (binned)
        bins.add<N - 3>(table, keys[kept], values[kept]);
      else
        table.prefetch(keys[kept++]);
    }
    for (int b = 0; b < kept; ++b) table.add_hit<N - 3>(keys[b], values[b]);
    done += batch;
  }
}

/// Adds the points a worker's bins still hold to its table (before the table is read).
template <int N>
void drain_job(VoxelTable& table, VoxelBins& bins) {
  bins.drain<N - 3>(table);
}

/// Voxels hit so far, and those hit exactly once and twice (f1, f2).
struct Occupancy {
  double voxels = 0, once = 0, twice = 0;
  /// @brief Chao1's estimate of the voxels no point has hit yet, bias-corrected so that it
  /// stays finite when no voxel was hit twice: f1 (f1 - 1) / (2 (f2 + 1)).
  double unseen() const { return once * (once - 1.0) / (2.0 * (twice + 1.0)); }
  void count(std::uint64_t hits) {
    voxels += 1;
    once += hits == 1;
    twice += hits == 2;
  }
};

Occupancy occupancy(const VoxelList& voxels) {
  Occupancy o;
  for (std::uint64_t h : voxels.hits) o.count(h);
  return o;
}

/// The union of the threads' tables, read in place (taking them between rounds cost more
/// than the points): a voxel counts in the first table that holds it, with its hits summed
/// over the tables (only up to 3: above 2 they no longer matter).
Occupancy occupancy(const std::vector<VoxelTable>& tables) {
  Occupancy o;
  for (std::size_t t = 0; t < tables.size(); ++t)
    tables[t].for_each([&](std::uint64_t key, std::uint64_t hits) {
      for (std::size_t u = 0; u < t; ++u)
        if (tables[u].hits_of(key) > 0) return;
      for (std::size_t u = t + 1; u < tables.size() && hits <= 2; ++u) hits += tables[u].hits_of(key);
      o.count(hits);
    });
  return o;
}

/// The tables' voxels as one sorted list (each table taken on its own thread).
VoxelList take_all(std::vector<VoxelTable>& tables, int threads) {
  std::vector<VoxelList> lists(tables.size());
  parallel_jobs(tables.size(), threads, [&](std::size_t t, int) { lists[t] = tables[t].take(); });
  return merge_voxel_lists(lists, threads);
}

using ChaosJob = void (*)(const Ifs&, const MapChain&, const VoxelGrid&, const ChannelQuantizer&,
                          std::uint64_t, std::uint64_t, std::uint64_t, VoxelTable&, VoxelBins&);

ChaosJob chaos_job_for(int dim) {
  static constexpr ChaosJob kJobs[] = {chaos_job<3>, chaos_job<4>, chaos_job<5>,
                                       chaos_job<6>, chaos_job<7>, chaos_job<8>};
  return kJobs[dim - 3];
}

/// Plots jobs [first, last) (job j: points [j, j + 1) * kPointsPerJob, capped at `limit`) into
/// the workers' tables. In the chain lanes where the CPU has them: tasks of up to kMaxChains jobs
/// side by side, those of a task of one count (only a render's last job may be shorter: it runs
/// on its own), added to the tables directly (voxel_chains_plan.cpp says why); else a job a task
/// in the one-job loop (through the bins where the table is large). The same points either way.
void plot_jobs(const Ifs& ifs, const MapChain& chain, const VolumeSetup& setup, std::uint64_t seed,
               std::uint64_t first, std::uint64_t last, std::uint64_t limit, int threads,
               std::vector<VoxelTable>& tables, std::vector<VoxelBins>& bins, const ProgressCallback& progress) {
  const VoxelChains lanes(ifs, chain, setup.grid, setup.quantizer);
  const ChaosJob run = chaos_job_for(ifs.dim());
  const std::uint64_t per_task = lanes.available() ? chains::jobs_per_task(last - first, threads) : 1;
  auto count_of = [&](std::uint64_t job) { return std::min(kPointsPerJob, limit - job * kPointsPerJob); };
  parallel_jobs((last - first + per_task - 1) / per_task, threads, [&](std::size_t k, int worker) {
    const std::uint64_t begin = first + k * per_task, end = std::min(last, begin + per_task);
    if (!lanes.available())
      return run(ifs, chain, setup.grid, setup.quantizer, count_of(begin), seed, begin, tables[worker], bins[worker]);
    const std::uint64_t full = count_of(end - 1) == count_of(begin) ? end : end - 1;
    lanes.run(begin, static_cast<int>(full - begin), count_of(begin), kSkip, seed, tables[worker]);
    if (full < end) lanes.run(full, 1, count_of(full), kSkip, seed, tables[worker]);
  }, progress);
}

/// Drains every worker's bins into its table, each on a thread of its own.
void drain_all(int dim, std::vector<VoxelTable>& tables, std::vector<VoxelBins>& bins, int threads) {
  using DrainJob = void (*)(VoxelTable&, VoxelBins&);
  static constexpr DrainJob kDrains[] = {drain_job<3>, drain_job<4>, drain_job<5>,
                                         drain_job<6>, drain_job<7>, drain_job<8>};
  parallel_jobs(tables.size(), threads, [&](std::size_t t, int) { kDrains[dim - 3](tables[t], bins[t]); });
}

}  // namespace

Capabilities RandomIterationVolume::capabilities() const {
  // Random iteration follows the walker (transitions).
  using C = Capabilities;
  return {C::Recurrent | C::AverageContractive | C::Overlapping | C::Space};
}

Volume RandomIterationVolume::draw(const Ifs& ifs, const VolumeOptions& options) const {
  const VolumeSetup setup = prepare_volume(ifs, options);
  const int channels = ifs.dim() - 3;
  // Each thread's table (at most half full) may meet every voxel; then the running total, the
  // merge and the volume. Refused before the first point, not when a table grows past it.
  // The bins of a large table (voxel_bins.h) cost a share of its bytes.
  const double per_voxel = setup.threads * VoxelTable::bytes_per_voxel(channels, false) *
                               (1.0 + VoxelBins::bytes_per_table_byte(channels)) +
                           2.0 * VoxelList::entry_bytes(channels) + 12.0 + 4.0 * channels;
  check_memory(expected_voxels(ifs, options, setup, per_voxel, 0.0) * per_voxel,
               "random iteration into a " + std::to_string(options.resolution) + "^3 volume");
  const MapChain chain(ifs);
  std::vector<VoxelTable> tables(setup.threads, VoxelTable(channels));
  std::vector<VoxelBins> bins(setup.threads, VoxelBins(channels));
  VoxelList total(channels);  // with `distribute`; otherwise the tables hold the points until the end
  std::uint64_t points = 0, jobs_done = 0;

  // Plots jobs [first, last) (job j: points [j, j + 1) * kPointsPerJob, capped at `limit`).
  // Job j always draws stream (seed, j): the result never depends on the threads or on how
  // the jobs were grouped into rounds. With `distribute`, the same jobs run elsewhere
  // (random_iteration_jobs) and merge here.
  auto round = [&](std::uint64_t first, std::uint64_t last, std::uint64_t limit, const ProgressCallback& progress) {
    if (options.distribute) {
      const std::vector<std::string_view> results = options.distribute(first, last);
      std::vector<VoxelList> lists(results.size() + 1);
      lists[0] = std::move(total);
      parallel_jobs(results.size(), setup.threads,
                    [&](std::size_t k, int) { lists[k + 1] = decode_volume_jobs(results[k]).voxels; });
      total = merge_voxel_lists(lists, setup.threads);
    } else {
      plot_jobs(ifs, chain, setup, options.seed, first, last, limit, setup.threads, tables, bins, progress);
      drain_all(ifs.dim(), tables, bins, setup.threads);
    }
    points = std::min(limit, last * kPointsPerJob);
    jobs_done = last;
  };

  if (options.iterations > 0) {
    const std::uint64_t jobs = (options.iterations + kPointsPerJob - 1) / kPointsPerJob;
    round(0, jobs, options.iterations, progress_range(options.progress, 0.0, 0.95));
  } else {
    // Rounds of points until Chao1's estimate of the occupied voxels no point has hit yet
    // (from the voxels hit once and twice) falls to kUnseen of those found: the volumetric
    // form of Eq. 45's coupon collector for an uneven measure, whose grazed voxels hold a
    // tiny share of it. Each round aims at the point count where the estimate, falling as a
    // power of the points (its exponent read from the last two rounds), meets the bound:
    // between +10% and +50%, so that no round overshoots by much.
    constexpr double kUnseen = 0.008;
    double unseen_before = 0.0, reported = 0.0;
    std::uint64_t last = 2, jobs_before = 0;
    while (last * kPointsPerJob <= kMaxAutoPoints) {
      const double next = reported + 0.5 * (0.95 - reported);
      round(jobs_done, last, last * kPointsPerJob, progress_range(options.progress, reported, next));
      reported = next;
      const Occupancy found = options.distribute ? occupancy(total) : occupancy(tables);
      if (found.voxels == 0.0) {
        if (jobs_before > 0) break;  // two rounds without a voxel: the bounds miss the attractor
      } else if (found.unseen() <= kUnseen * found.voxels) {
        break;
      }
      double factor = 1.5;
      if (unseen_before > found.unseen() && found.unseen() > 0.0)
        factor = std::pow(found.unseen() / (kUnseen * found.voxels),
                          std::log(double(last) / double(jobs_before)) / std::log(unseen_before / found.unseen()));
      jobs_before = last;
      unseen_before = found.unseen();
      last = std::max(last + 1, static_cast<std::uint64_t>(std::ceil(double(last) * std::clamp(factor, 1.1, 1.5))));
    }
  }
  if (!options.distribute) total = take_all(tables, setup.threads);
  Volume volume = finish_volume(std::move(total), setup.grid, ifs, setup.quantizer, options.density,
                                static_cast<double>(points), setup.threads);
  volume.algorithm = name();
  volume.points = points;
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  return volume;
}

std::string RandomIterationVolume::draw_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                                             std::uint64_t last) const {
  const VolumeSetup setup = prepare_volume(ifs, options);
  const int channels = ifs.dim() - 3;
  const MapChain chain(ifs);
  // render()'s point cap: the requested count, or whole jobs while doubling.
  const std::uint64_t limit = options.iterations > 0 ? options.iterations : last * kPointsPerJob;
  last = std::min(last, (limit + kPointsPerJob - 1) / kPointsPerJob);
  const int threads = static_cast<int>(std::min<std::uint64_t>(setup.threads, std::max(first, last) - first));
  std::vector<VoxelTable> tables(std::max(1, threads), VoxelTable(channels));
  std::vector<VoxelBins> bins(std::max(1, threads), VoxelBins(channels));
  VolumeJobsResult out;
  if (first < last)
    plot_jobs(ifs, chain, setup, options.seed, first, last, limit, threads, tables, bins, options.progress);
  drain_all(ifs.dim(), tables, bins, setup.threads);
  out.voxels = take_all(tables, setup.threads);
  for (std::uint64_t job = first; job < last; ++job) out.points += std::min(kPointsPerJob, limit - job * kPointsPerJob);
  return encode_volume_jobs(out, options.density);
}

}  // namespace ifsforge
