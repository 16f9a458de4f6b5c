#include "staged_jobs.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

void staged_jobs(const std::vector<std::size_t>& middles, int threads,
                 const std::function<void(std::size_t unit)>& first,
                 const std::function<void(std::size_t unit, std::size_t item)>& middle,
                 const std::function<void(std::size_t unit, std::size_t item)>& follow,
                 const ProgressCallback& progress) {
  const std::size_t units = middles.size();
  std::size_t tasks = units;
  for (std::size_t m : middles) tasks += 2 * m;
  std::vector<std::vector<char>> ended(units);
  for (std::size_t u = 0; u < units; ++u) ended[u].assign(middles[u], 0);
  // Per unit: its first has ended; a thread runs its follow; follows run so far; middles taken.
  std::vector<char> first_done(units, 0), following(units, 0);
  std::vector<std::size_t> followed(units, 0), taken(units, 0);
  std::size_t firsts_taken = 0, finished = 0;
  std::atomic<std::size_t> done{0};
  std::mutex mutex;
  std::condition_variable changed;
  enum Kind { kNone, kFirst, kMiddle, kFollow };
  struct Task {
    Kind kind;
    std::size_t unit, item;
  };
  // The next task, units in priority order (the first listed are the costliest): an unstarted
  // first, else the unit's next follow once its middle has ended and no thread runs one, else
  // its lowest middle not yet taken (the follow's own, or one ahead of a running follow).
  const auto choose = [&]() -> Task {
    if (firsts_taken < units) return {kFirst, firsts_taken++, 0};
    for (std::size_t u = 0; u < units; ++u) {
      if (!first_done[u] || followed[u] == middles[u]) continue;
      if (!following[u] && ended[u][followed[u]]) {
        following[u] = 1;
        return {kFollow, u, followed[u]};
      }
      if (taken[u] < middles[u]) return {kMiddle, u, taken[u]++};
    }
    return {kNone, 0, 0};
  };
  const auto worker = [&](std::size_t, int) {
    std::unique_lock<std::mutex> lock(mutex);
    while (finished < units) {
      if (stop_requested()) throw Cancelled();
      const Task t = choose();
      if (t.kind == kNone) {
        changed.wait_for(lock, std::chrono::milliseconds(10));
        continue;
      }
      lock.unlock();
      if (t.kind == kFirst) first(t.unit);
      else if (t.kind == kMiddle) middle(t.unit, t.item);
      else follow(t.unit, t.item);
      ++done;
      lock.lock();
      const std::size_t u = t.unit;
      if (t.kind == kFirst) first_done[u] = 1;
      else if (t.kind == kMiddle) ended[u][t.item] = 1;
      else {
        following[u] = 0;
        ++followed[u];
      }
      if (t.kind != kMiddle && first_done[u] && followed[u] == middles[u] && !following[u]) ++finished;
      changed.notify_all();
    }
  };
  // One job per thread, each taking tasks until every unit is finished; progress counts tasks.
  const int workers = resolve_threads(threads);
  ProgressCallback report;
  if (progress)
    report = [&](double fraction) { return progress(fraction >= 1.0 ? 1.0 : double(done.load()) / double(tasks)); };
  parallel_jobs(std::size_t(workers), workers, worker, report);
}

}  // namespace ifsforge
