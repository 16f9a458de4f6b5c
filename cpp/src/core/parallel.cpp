#include "ifsforge/core/parallel.h"

#include "ifsforge/core/default_threads.h"

#include <atomic>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge {

namespace {
std::atomic<int> default_threads{0};
}

void set_default_threads(int threads) {
  if (threads < 0) throw InputError("threads must be >= 0 (0: all cores), got " + std::to_string(threads));
  default_threads = threads;
}

int resolve_threads(int requested) {
  if (requested > 0) return requested;
  if (const int preset = default_threads.load(); preset > 0) return preset;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

void parallel_jobs(std::size_t jobs, int threads,
                   const std::function<void(std::size_t, int)>& job,
                   const ProgressCallback& progress) {
  threads = resolve_threads(threads);
  if (static_cast<std::size_t>(threads) > jobs) threads = static_cast<int>(jobs > 0 ? jobs : 1);
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  std::mutex failure_mutex;

  auto run = [&](int worker, bool reporter) {
    for (;;) {
      if (stop.load(std::memory_order_relaxed)) return;
      const std::size_t index = next.fetch_add(1);
      if (index >= jobs) return;
      try {
        job(index, worker);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
        return;
      }
      const std::size_t finished = done.fetch_add(1) + 1;
      if (!reporter || !progress) continue;
      // The callback may throw (a Python error): stop the workers before passing it on.
      std::exception_ptr stopped;
      try {
        if (!progress(static_cast<double>(finished) / jobs)) stopped = std::make_exception_ptr(Cancelled());
      } catch (...) {
        stopped = std::current_exception();
      }
      if (stopped) {
        stop = true;
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = stopped;
        return;
      }
    }
  };

  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  for (int w = 1; w < threads; ++w) pool.emplace_back(run, w, false);
  run(0, true);
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  if (progress && !progress(1.0)) throw Cancelled();
}

}  // namespace ifsforge
