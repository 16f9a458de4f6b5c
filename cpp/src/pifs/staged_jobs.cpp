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
                 const std::function<void(std::size_t unit, std::size_t item)>& follow,
                 const ProgressCallback& progress) {
  const std::size_t units = middles.size();
  std::size_t total = 0;
  for (std::size_t m : middles) total += m;
  enum Item : char { kWaiting, kRunning, kEnded };
  std::vector<std::vector<char>> items(units);
  for (std::size_t u = 0; u < units; ++u) items[u].assign(middles[u], kWaiting);
  std::vector<char> first_done(units, 0), followed(units, 0);
  std::vector<std::size_t> unstarted(middles);  // per unit: middles nobody has taken
  std::mutex mutex;
  std::condition_variable changed;
  const auto wait = [&](std::unique_lock<std::mutex>& lock) {
    if (stop_requested()) throw Cancelled();
    changed.wait_for(lock, std::chrono::milliseconds(10));
  };
  const auto run_middle = [&](std::size_t u, std::size_t i) {
    middle(u, i);
    std::lock_guard<std::mutex> lock(mutex);
    items[u][i] = kEnded;
    changed.notify_all();
  };
  // The follower of unit u: item i's middle, unless another thread has it, then its follow;
  // while another thread ends item i, the follower runs a later middle of its unit.
  const auto run_follower = [&](std::size_t u) {
    for (std::size_t i = 0; i < middles[u]; ++i) {
      std::unique_lock<std::mutex> lock(mutex);
      while (items[u][i] != kEnded) {
        std::size_t j = i;
        while (j < middles[u] && items[u][j] != kWaiting) ++j;
        if (j == middles[u]) {
          wait(lock);
          continue;
        }
        items[u][j] = kRunning;
        --unstarted[u];
        lock.unlock();
        run_middle(u, j);
        lock.lock();
      }
      lock.unlock();
      follow(u, i);
    }
  };
  // Jobs start in index order: the firsts, then slots that each take one task (a middle, or a
  // unit's follower), or none once every task is taken. A slot waits only for firsts or
  // middles already running on other threads, so every wait ends.
  parallel_jobs(
      units + total + units, threads,
      [&](std::size_t job, int) {
        if (job < units) {
          first(job);
          std::lock_guard<std::mutex> lock(mutex);
          first_done[job] = 1;
          changed.notify_all();
          return;
        }
        std::unique_lock<std::mutex> lock(mutex);
        for (;;) {
          std::size_t lead = units, ready = units, idle = units;
          bool left = false;  // a task not yet taken
          for (std::size_t u = 0; u < units; ++u) {
            left = left || !followed[u] || unstarted[u] > 0;
            if (!first_done[u]) continue;
            if (!followed[u] && idle == units) idle = u;
            if (unstarted[u] == 0) continue;
            if (followed[u] && lead == units) lead = u;
            if (ready == units) ready = u;
          }
          if (!left) return;
          // Middles a follower waits for first; then a new follower (it runs its own middles
          // when no other thread has them, so starting it early never idles a thread); then
          // any middle.
          const std::size_t start = lead == units ? idle : units;
          if (start < units) {
            followed[start] = 1;
            lock.unlock();
            run_follower(start);
            return;
          }
          const std::size_t u = lead < units ? lead : ready;
          if (u < units) {
            std::size_t i = 0;
            while (items[u][i] != kWaiting) ++i;
            items[u][i] = kRunning;
            --unstarted[u];
            lock.unlock();
            run_middle(u, i);
            return;
          }
          wait(lock);
        }
      },
      progress);
}

}  // namespace ifsforge
