#pragma once
/// @file Deterministic parallelism: work is cut into a fixed number of jobs that does not
/// depend on the thread count, so results merged by exact (integer or ordered) reduction
/// are identical for any number of threads.
#include <cstddef>
#include <functional>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// @brief Threads to use: `requested` if > 0, else the hardware concurrency.
int resolve_threads(int requested);

/// @brief Runs job(index, worker) for every index in [0, jobs) on `threads` threads.
/// `worker` in [0, threads) identifies per-thread scratch (accumulators). Without `progress`
/// the calling thread takes part; with it, the calling thread only reports (every 0.1 s) and a
/// false return stops the work and throws Cancelled. The first exception of a job propagates.
/// Which job runs on which worker never changes the result (jobs merge in index order).
void parallel_jobs(std::size_t jobs, int threads,
                   const std::function<void(std::size_t job, int worker)>& job,
                   const ProgressCallback& progress = nullptr);

/// @brief True inside a job of parallel_jobs once the work is stopping (cancelled, or another
/// job failed): a job that runs for long checks it now and then and throws Cancelled.
bool stop_requested();

}  // namespace ifsforge
