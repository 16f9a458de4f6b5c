#include "staged_jobs.h"

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

void staged_jobs(const std::vector<std::size_t>& middles, int threads,
                 const std::function<void(std::size_t unit)>& first,
                 const std::function<void(std::size_t unit, std::size_t item)>& middle,
                 const std::function<void(std::size_t unit)>& last, const ProgressCallback& progress) {
  const std::size_t units = middles.size();
  std::size_t total = 0;
  for (std::size_t m : middles) total += m;
  // Per unit: its first step has ended; middles handed out; middles ended; last handed out.
  std::vector<char> first_done(units, 0), last_taken(units, 0);
  std::vector<std::size_t> handed(units, 0), ended(units, 0);
  std::mutex mutex;
  std::condition_variable changed;
  // Jobs start in index order: the firsts, then `total` middle slots, then `units` last slots.
  // A slot takes the first ready step of its kind; all the steps it could wait for were handed
  // out to running threads before it started, so every wait ends.
  const auto take = [&](const auto& ready) {
    std::unique_lock<std::mutex> lock(mutex);
    for (;;) {
      for (std::size_t u = 0; u < units; ++u)
        if (ready(u)) return u;
      if (stop_requested()) throw Cancelled();
      changed.wait_for(lock, std::chrono::milliseconds(10));
    }
  };
  const auto ended_step = [&](auto&& mark) {
    std::lock_guard<std::mutex> lock(mutex);
    mark();
    changed.notify_all();
  };
  parallel_jobs(
      units + total + units, threads,
      [&](std::size_t job, int) {
        if (job < units) {
          first(job);
          ended_step([&] { first_done[job] = 1; });
        } else if (job < units + total) {
          std::size_t item = 0;
          const std::size_t u = take([&](std::size_t v) {
            if (!first_done[v] || handed[v] == middles[v]) return false;
            item = handed[v]++;
            return true;
          });
          middle(u, item);
          ended_step([&] { ++ended[u]; });
        } else {
          const std::size_t u = take([&](std::size_t v) {
            if (last_taken[v] || !first_done[v] || ended[v] < middles[v]) return false;
            last_taken[v] = 1;
            return true;
          });
          last(u);
        }
      },
      progress);
}

}  // namespace ifsforge
