#pragma once
// Where a process's threads spent a run, from the kernel's per-thread scheduler statistics
// (/proc/self/task/*/schedstat, Linux with CONFIG_SCHED_INFO): time on a CPU and time runnable
// but waiting for one. On N threads over a wall time W, N·W − run − waiting is the time the
// threads slept (waiting for work: the code's serial part; workers_slept counts it per thread),
// while the waiting is the machine's (other processes, late wake-ups of an idle core): the split
// a wall-clock share cannot make.
#include <dirent.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>

namespace bench {

/// One thread's sums: seconds on a CPU and runnable waiting for one.
struct ThreadTimes {
  double run = 0, waiting = 0;
};

struct ThreadSchedule {
  double run = 0, waiting = 0;  ///< seconds, summed over the process's threads
  bool known = false;           ///< false where the kernel keeps no statistics
  std::map<long, ThreadTimes> threads;  ///< each thread's, by thread id
};

/// The sums now; differences of two readings cover a run (threads never end in the library's
/// pool, so none of a run's time is lost with its thread).
inline ThreadSchedule thread_schedule() {
  ThreadSchedule s;
  DIR* tasks = opendir("/proc/self/task");
  if (!tasks) return s;
  while (const dirent* entry = readdir(tasks)) {
    if (entry->d_name[0] == '.') continue;
    const std::string path = std::string("/proc/self/task/") + entry->d_name + "/schedstat";
    if (FILE* f = std::fopen(path.c_str(), "r")) {
      unsigned long long run = 0, waiting = 0;
      if (std::fscanf(f, "%llu %llu", &run, &waiting) == 2) {
        const ThreadTimes t{1e-9 * double(run), 1e-9 * double(waiting)};
        s.run += t.run;
        s.waiting += t.waiting;
        s.threads[std::atol(entry->d_name)] = t;
        s.known = true;
      }
      std::fclose(f);
    }
  }
  closedir(tasks);
  return s;
}

/// The seconds the threads of a run of `wall` seconds on `n` threads slept, from readings
/// `before` and `after` it: the calling thread's wall - run - waiting, and the others' (n - 1) wall
/// less their run and waiting, summed over every other thread that ran but at most (n - 1) wall.
/// Summed over every thread as n wall - run - waiting, a thread one more than n (a nested parallel
/// call's helper started while the others were busy, as a first-touch fault inside a job starts
/// one, or the .vdb writer's flush thread) made the share negative: its time, and the others'
/// wait for a CPU while it ran, were counted against n walls. Taken thread by thread instead, a
/// pool's helpers that take turns (each ran part of the run) would count as sleeping.
inline double workers_slept(const ThreadSchedule& before, const ThreadSchedule& after, int n, double wall) {
  const long caller = static_cast<long>(getpid());  // the main thread's id: the runs are called from it
  double own = wall, others = 0;
  for (const auto& [id, t] : after.threads) {
    const auto was = before.threads.find(id);
    const ThreadTimes from = was == before.threads.end() ? ThreadTimes{} : was->second;  // started in the run
    const double active = (t.run - from.run) + (t.waiting - from.waiting);
    if (id == caller)
      own -= active;
    else
      others += active;
  }
  return own + std::max(0.0, (n - 1) * wall - others);
}

}  // namespace bench
