#include "staged_rounds.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"

namespace ifsforge {
namespace {

/// How long a thread with nothing to do spins before it sleeps (see `idle` below).
constexpr std::chrono::microseconds kSpin{2000};

/// One spin of a busy wait: yields the core to any thread waiting for it (on a machine busier
/// than its cores, the thread whose step this one waits for), else returns at once.
inline void relax() { std::this_thread::yield(); }

}  // namespace

void staged_rounds(const std::function<bool(std::vector<std::size_t>& middles)>& next_round, int threads,
                   const std::function<std::vector<std::size_t>(std::size_t unit)>& first,
                   const std::function<void(std::size_t unit, std::size_t stage, std::size_t part)>& part,
                   const std::function<void(std::size_t unit, std::size_t item)>& middle,
                   const std::function<void(std::size_t unit, std::size_t item)>& follow,
                   const ProgressCallback& progress) {
  // The round's units: middles, middles ended, whether the first has ended and a thread runs a
  // follow, follows run so far, middles taken; the parts of each stage (first's answer), the
  // stage running and its parts taken and ended.
  std::vector<std::size_t> middles;
  std::vector<std::vector<char>> ended;
  std::vector<char> first_done, following;
  std::vector<std::size_t> followed, taken;
  std::vector<std::vector<std::size_t>> stages;
  std::vector<std::size_t> stage, parts_taken, parts_ended;
  std::size_t units = 0, firsts_taken = 0, finished = 0;
  bool between = false, over = false;  // a thread runs next_round; no round is left
  std::atomic<std::size_t> done{0}, tasks{1}, rounds{0};  // read by the progress report
  std::mutex mutex;
  std::condition_variable changed;
  // Bumped (under the mutex) at every change a waiting thread may be waiting for, so a thread
  // that finds nothing to do can spin on it before it sleeps.
  std::atomic<std::uint64_t> version{0};
  const auto notify = [&] {
    version.fetch_add(1, std::memory_order_release);
    changed.notify_all();
  };
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
    stages.assign(units, {});
    stage.assign(units, 0);
    parts_taken.assign(units, 0);
    parts_ended.assign(units, 0);
    firsts_taken = finished = 0;
    done = 0;
    tasks = count;
  };
  enum Kind { kNone, kFirst, kPart, kMiddle, kFollow };
  struct Task {
    Kind kind;
    std::size_t unit, item, stage;
  };
  // Past the stages without parts.
  const auto skip_empty = [&](std::size_t u) {
    while (stage[u] < stages[u].size() && stages[u][stage[u]] == 0) ++stage[u];
  };
  const auto unit_over = [&](std::size_t u) {
    return first_done[u] && stage[u] == stages[u].size() && followed[u] == middles[u] && !following[u];
  };
  // The next task, units in priority order (the first listed are the costliest): an unstarted
  // first, else the unit's next part of its running stage, else (its stages done) its next
  // follow once its middle has ended and no thread runs one, else its lowest middle not yet
  // taken (the follow's own, or one ahead of a running follow).
  const auto choose = [&]() -> Task {
    if (firsts_taken < units) return {kFirst, firsts_taken++, 0, 0};
    for (std::size_t u = 0; u < units; ++u) {
      if (!first_done[u]) continue;
      if (stage[u] < stages[u].size()) {
        if (parts_taken[u] < stages[u][stage[u]]) return {kPart, u, parts_taken[u]++, stage[u]};
        continue;  // the stage's last parts are running
      }
      if (followed[u] == middles[u]) continue;
      if (!following[u] && ended[u][followed[u]]) {
        following[u] = 1;
        return {kFollow, u, followed[u], 0};
      }
      if (taken[u] < middles[u]) return {kMiddle, u, taken[u]++, 0};
    }
    return {kNone, 0, 0, 0};
  };
  // A thread with nothing to do spins a while before it sleeps: the work it waits for (the
  // step that ends a round, next_round, the middle a follow needs, the tail of a round's
  // follows) mostly comes within a millisecond or two, while waking a sleeping thread took 2 to
  // 4.5 ms on the 2-core VM (an idle virtual core is halted): at 1024² a tenth of a round. The
  // spin is bounded, so a longer wait costs at most kSpin of CPU, and it yields: where the
  // machine gave the encode one core, a spin of pauses held it while the step it waited for
  // queued behind it (half the spins ran the full 2 ms), and yielding hands the core over (none
  // did). The sleep's timeout only bounds a missed notification.
  const auto idle = [&](std::unique_lock<std::mutex>& lock) {
    const std::uint64_t seen = version.load(std::memory_order_acquire);
    lock.unlock();
    const auto until = std::chrono::steady_clock::now() + kSpin;
    bool moved = false;
    while (!(moved = version.load(std::memory_order_acquire) != seen) && std::chrono::steady_clock::now() < until)
      relax();
    lock.lock();
    if (!moved && version.load(std::memory_order_relaxed) == seen) changed.wait_for(lock, std::chrono::milliseconds(10));
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
        notify();
        continue;
      }
      const Task t = between ? Task{kNone, 0, 0, 0} : choose();
      if (t.kind == kNone) {
        idle(lock);
        continue;
      }
      lock.unlock();
      std::vector<std::size_t> parts;
      if (t.kind == kFirst) parts = first(t.unit);
      else if (t.kind == kPart) part(t.unit, t.stage, t.item);
      else if (t.kind == kMiddle) middle(t.unit, t.item);
      else follow(t.unit, t.item);
      ++done;
      lock.lock();
      const std::size_t u = t.unit;
      if (t.kind == kFirst) {
        first_done[u] = 1;
        for (std::size_t n : parts) tasks += n;
        stages[u] = std::move(parts);
        skip_empty(u);
      } else if (t.kind == kPart) {
        if (++parts_ended[u] == stages[u][stage[u]]) {
          ++stage[u];
          parts_taken[u] = parts_ended[u] = 0;
          skip_empty(u);
        }
      } else if (t.kind == kMiddle) {
        ended[u][t.item] = 1;
      } else {
        following[u] = 0;
        ++followed[u];
      }
      if (t.kind != kMiddle && unit_over(u)) ++finished;
      notify();
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
