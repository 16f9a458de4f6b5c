#include "ifsforge/volume/random_iteration_volume.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/fixed_maps.h"
#include "ifsforge/model/map_sampler.h"
#include "voxel_table.h"

namespace ifsforge {
namespace {

constexpr std::uint64_t kPointsPerJob = std::uint64_t(1) << 20;
constexpr std::uint64_t kSkip = 100;  // min_no_of_iterations of 5.1.1
constexpr std::uint64_t kMaxAutoPoints = std::uint64_t(1) << 34;

/// One job of the chaos game in N dimensions (a template parameter, so the map unrolls).
template <int N>
void chaos_job(const Ifs& ifs, const MapSampler& sampler, const VoxelGrid& grid,
               const ChannelQuantizer& quantizer, std::uint64_t points, std::uint64_t seed,
               std::uint64_t job, VoxelTable& table) {
  const auto maps = fixed_maps<N>(ifs);
  Rng rng(seed, job);
  const Point start = ifs.start_point();
  double p[N], q[N];
  for (int c = 0; c < N; ++c) p[c] = start[c];
  auto step = [&] {
    const auto& m = maps[sampler(rng.next())];
    for (int r = 0; r < N; ++r) {
      double value = m.b[r];
      for (int c = 0; c < N; ++c) value += m.a[r][c] * p[c];
      q[r] = value;
    }
    for (int c = 0; c < N; ++c) p[c] = q[c];
  };
  for (std::uint64_t i = 0; i < kSkip; ++i) step();
  // Points go in batches: every key of a batch is computed and its slot prefetched before
  // the first add, so the table's cache misses overlap instead of stalling one by one.
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
      table.prefetch(keys[kept++]);
    }
    for (int b = 0; b < kept; ++b) table.add(keys[b], 1, 1, values[b]);
    done += batch;
  }
}

using ChaosJob = void (*)(const Ifs&, const MapSampler&, const VoxelGrid&, const ChannelQuantizer&,
                          std::uint64_t, std::uint64_t, std::uint64_t, VoxelTable&);

ChaosJob chaos_job_for(int dim) {
  static constexpr ChaosJob kJobs[] = {chaos_job<3>, chaos_job<4>, chaos_job<5>,
                                       chaos_job<6>, chaos_job<7>, chaos_job<8>};
  return kJobs[dim - 3];
}

}  // namespace

Volume RandomIterationVolume::render(const Ifs& ifs, const VolumeOptions& options) const {
  const VolumeSetup setup = prepare_volume(ifs, options);
  const int channels = ifs.dim() - 3;
  // Each thread's table (at most half full) may meet every voxel; then the running total, the
  // merge and the volume. Refused before the first point, not when a table grows past it.
  const double per_voxel =
      setup.threads * VoxelTable::bytes_per_voxel(channels, false) + 2.0 * VoxelList::entry_bytes(channels) + 12.0 +
      4.0 * channels;
  check_memory(expected_voxels(ifs, options, setup, per_voxel, 0.0) * per_voxel,
               "random iteration into a " + std::to_string(options.resolution) + "^3 volume");
  const MapSampler sampler(ifs.probabilities());
  const ChaosJob run = chaos_job_for(ifs.dim());
  std::vector<VoxelTable> tables(setup.threads, VoxelTable(channels));
  VoxelList total(channels);
  std::uint64_t points = 0, jobs_done = 0;

  // Plots jobs [first, last) (job j: points [j, j + 1) * kPointsPerJob, capped at `limit`) and
  // adds them to `total`. Job j always draws stream (seed, j): the result never depends on
  // the threads or on how the jobs were grouped into rounds.
  // With `distribute`, the same jobs run elsewhere (random_iteration_jobs) and merge here.
  auto round = [&](std::uint64_t first, std::uint64_t last, std::uint64_t limit, const ProgressCallback& progress) {
    std::vector<VoxelList> lists;
    lists.push_back(std::move(total));
    if (options.distribute) {
      for (VolumeJobsResult& r : options.distribute(first, last)) lists.push_back(std::move(r.voxels));
    } else {
      parallel_jobs(last - first, setup.threads, [&](std::size_t k, int worker) {
        const std::uint64_t job = first + k;
        const std::uint64_t count = std::min(kPointsPerJob, limit - job * kPointsPerJob);
        run(ifs, sampler, setup.grid, setup.quantizer, count, options.seed, job, tables[worker]);
      }, progress);
      for (VoxelTable& t : tables) lists.push_back(t.take());
    }
    total = merge_voxel_lists(lists, setup.threads);
    points = std::min(limit, last * kPointsPerJob);
    jobs_done = last;
  };

  if (options.iterations > 0) {
    const std::uint64_t jobs = (options.iterations + kPointsPerJob - 1) / kPointsPerJob;
    round(0, jobs, options.iterations, progress_range(options.progress, 0.0, 0.95));
  } else {
    // Add points in rounds of +50% until occupancy's growth falls below 1% per doubling of
    // the points (new voxels / voxels < 1% of new points / points): the volumetric form of
    // Eq. 45's coupon collector. Voxels the attractor only grazes hold a tiny share of the
    // measure and would need ever more points. Rounds of +50% (rather than doubling) measure
    // that slope without spending a whole doubling past it.
    std::size_t before = 0;
    std::uint64_t points_before = 0;
    double reported = 0.0;
    for (std::uint64_t last = 2; last * kPointsPerJob <= kMaxAutoPoints; last += (last + 1) / 2) {
      const double next = reported + 0.5 * (0.95 - reported);
      round(jobs_done, last, last * kPointsPerJob, progress_range(options.progress, reported, next));
      reported = next;
      if (points_before > 0) {
        if (total.size() == 0) break;  // two rounds without a voxel: the bounds miss the attractor
        const double growth = double(total.size() - before) / double(std::max<std::size_t>(before, 1));
        if (growth < 0.01 * double(points - points_before) / double(points_before)) break;
      }
      before = total.size();
      points_before = points;
    }
  }
  Volume volume = finish_volume(std::move(total), setup.grid, ifs, setup.quantizer, options.density,
                                static_cast<double>(points), setup.threads);
  volume.algorithm = name();
  volume.points = points;
  if (options.progress && !options.progress(1.0)) throw Cancelled();
  return volume;
}

VolumeJobsResult RandomIterationVolume::run_jobs(const Ifs& ifs, const VolumeOptions& options, std::uint64_t first,
                                                 std::uint64_t last) const {
  const VolumeSetup setup = prepare_volume(ifs, options);
  const int channels = ifs.dim() - 3;
  const MapSampler sampler(ifs.probabilities());
  const ChaosJob run = chaos_job_for(ifs.dim());
  // render()'s point cap: the requested count, or whole jobs while doubling.
  const std::uint64_t limit = options.iterations > 0 ? options.iterations : last * kPointsPerJob;
  last = std::min(last, (limit + kPointsPerJob - 1) / kPointsPerJob);
  const int threads = static_cast<int>(std::min<std::uint64_t>(setup.threads, std::max(first, last) - first));
  std::vector<VoxelTable> tables(std::max(1, threads), VoxelTable(channels));
  VolumeJobsResult out;
  if (first < last)
    parallel_jobs(last - first, threads, [&](std::size_t k, int worker) {
      const std::uint64_t job = first + k;
      const std::uint64_t count = std::min(kPointsPerJob, limit - job * kPointsPerJob);
      run(ifs, sampler, setup.grid, setup.quantizer, count, options.seed, job, tables[worker]);
    }, options.progress);
  std::vector<VoxelList> lists;
  for (VoxelTable& t : tables) lists.push_back(t.take());
  out.voxels = merge_voxel_lists(lists, setup.threads);
  for (std::uint64_t job = first; job < last; ++job) out.points += std::min(kPointsPerJob, limit - job * kPointsPerJob);
  return out;
}

}  // namespace ifsforge
