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
/// `worker` in [0, threads) identifies per-thread scratch (accumulators). The calling thread
/// takes part and reports progress after each job it finishes; a false return from the
/// callback stops the remaining jobs and throws Cancelled. Exceptions in jobs propagate.
void parallel_jobs(std::size_t jobs, int threads,
                   const std::function<void(std::size_t job, int worker)>& job,
                   const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
