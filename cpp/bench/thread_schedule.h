#pragma once
// Where a process's threads spent a run, from the kernel's per-thread scheduler statistics
// (/proc/self/task/*/schedstat, Linux with CONFIG_SCHED_INFO): time on a CPU and time runnable
// but waiting for one. On N threads over a wall time W, N·W − run − waiting is the time the
// threads slept (waiting for work: the code's serial part), while the waiting is the machine's
// (other processes, late wake-ups of an idle core): the split a wall-clock share cannot make.
#include <dirent.h>

#include <cstdio>
#include <string>

namespace bench {

struct ThreadSchedule {
  double run = 0, waiting = 0;  ///< seconds, summed over the process's threads
  bool known = false;           ///< false where the kernel keeps no statistics
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
        s.run += 1e-9 * double(run);
        s.waiting += 1e-9 * double(waiting);
        s.known = true;
      }
      std::fclose(f);
    }
  }
  closedir(tasks);
  return s;
}

}  // namespace bench
