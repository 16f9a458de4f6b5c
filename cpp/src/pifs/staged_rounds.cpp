#include "staged_rounds.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {

void staged_rounds(const std::function<bool(std::vector<std::size_t>& middles)>& next_round, int threads,
                   const std::function<void(std::size_t unit)>& first,
                   const std::function<void(std::size_t unit, std::size_t item)>& middle,
                   const std::function<void(std::size_t unit, std::size_t item)>& follow,
                   const ProgressCallback& progress) {
  // The round's units: middles, middles ended, whether the first has ended and a thread runs a
  // follow, follows run so far, middles taken.
  std::vector<std::size_t> middles;
  std::vector<std::vector<char>> ended;
  std::vector<char> first_done, following;
  std::vector<std::size_t> followed, taken;
  std::size_t units = 0, firsts_taken = 0, finished = 0;
  bool between = false, over = false;  // a thread runs next_round; no round is left
  std::atomic<std::size_t> done{0}, tasks{1}, rounds{0};  // read by the progress report
  std::mutex mutex;
  std::condition_variable changed;
  const auto start_round = [&] {
    units = middles.size();
    ended.assign(units, {});
    std::size_t count = units;
    for (std::size_t u = 0; u < units; ++u) {
      ended[u].assign(middles[u], 0);
      count += 2 * middles[u];
    }
    first_done.assign(units, 0);
    following.assign(units, 0);
    followed.assign(units, 0);
    taken.assign(units, 0);
    firsts_taken = finished = 0;
    done = 0;
    tasks = count;
  };
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
    for (;;) {
      if (stop_requested()) throw Cancelled();
      if (over) return;
      if (!between && finished == units) {
        // The round has ended: this thread starts the next while the others wait (its steps
        // need every result of this one).
        between = true;
        lock.unlock();
        std::vector<std::size_t> next;
        const bool more = next_round(next);
        lock.lock();
        between = false;
        over = !more;
        if (more) {
          middles = std::move(next);
          ++rounds;
          start_round();
        }
        changed.notify_all();
        continue;
      }
      const Task t = between ? Task{kNone, 0, 0} : choose();
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
  // One job per thread, each taking tasks until no round is left: the threads outlive the
  // rounds, so none is started (a new thread waits for a time slice on a busy machine) between
  // them.
  const int workers = resolve_threads(threads);
  ProgressCallback report;
  if (progress)
    report = [&](double fraction) {
      if (fraction >= 1.0) return progress(double(rounds.load()));
      const double round = double(rounds.load()) - 1.0;
      return progress(round < 0 ? 0.0 : round + double(done.load()) / double(tasks.load()));
    };
  parallel_jobs(std::size_t(workers), workers, worker, report);
}

}  // namespace ifsforge
