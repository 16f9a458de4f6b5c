#include "ifsforge/core/parallel.h"

#include "ifsforge/core/default_threads.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "ifsforge/core/error.h"

namespace ifsforge {

namespace {
std::atomic<int> default_threads{0};

/// The stop flag of the parallel_jobs whose job runs on this thread (nested calls restore it).
thread_local const std::atomic<bool>* current_stop = nullptr;

struct StopScope {
  explicit StopScope(const std::atomic<bool>* stop) : saved(current_stop) { current_stop = stop; }
  ~StopScope() { current_stop = saved; }
  const std::atomic<bool>* saved;
};
}  // namespace

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

bool stop_requested() { return current_stop && current_stop->load(std::memory_order_relaxed); }

void parallel_jobs(std::size_t jobs, int threads,
                   const std::function<void(std::size_t, int)>& job,
                   const ProgressCallback& progress) {
  threads = resolve_threads(threads);
  if (static_cast<std::size_t>(threads) > jobs) threads = static_cast<int>(jobs > 0 ? jobs : 1);
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> done{0};
  std::atomic<bool> stop{false};
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable changed;
  auto fail = [&](std::exception_ptr e) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!failure) failure = e;
    stop = true;
    changed.notify_all();
  };

  auto run = [&](int worker) {
    const StopScope scope(&stop);
    for (;;) {
      if (stop.load(std::memory_order_relaxed)) return;
      const std::size_t index = next.fetch_add(1);
      if (index >= jobs) return;
      try {
        job(index, worker);
      } catch (...) {
        fail(std::current_exception());
        return;
      }
      if (done.fetch_add(1) + 1 == jobs) {
        std::lock_guard<std::mutex> lock(mutex);
        changed.notify_all();
      }
    }
  };

  // With a callback the calling thread does no job: it reports every 0.1 s and cancels, so a
  // single long job (the fern's densest address prefix at 6000^2 runs for half a minute) does
  // not hold Ctrl-C; jobs see the stop through stop_requested().
  const bool supervise = static_cast<bool>(progress);
  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (int w = supervise ? 0 : 1; w < threads; ++w) pool.emplace_back(run, w);
  if (supervise) {
    // The predicate is checked before waiting: work that ended before this line costs no wait.
    auto over = [&] { return stop.load() || done.load() >= jobs; };
    std::unique_lock<std::mutex> lock(mutex);
    while (!changed.wait_for(lock, std::chrono::milliseconds(100), over)) {
      lock.unlock();
      // The callback may throw (a Python error): stop the workers before passing it on.
      std::exception_ptr stopped;
      try {
        if (!progress(static_cast<double>(done.load()) / static_cast<double>(jobs))) stopped = std::make_exception_ptr(Cancelled());
      } catch (...) {
        stopped = std::current_exception();
      }
      if (stopped) fail(stopped);
      lock.lock();
    }
  } else {
    run(0);
  }
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
  if (progress && !progress(1.0)) throw Cancelled();
}

}  // namespace ifsforge
