#pragma once
// Wall and CPU time (every thread of the process, user + system) of a call, best of a few runs:
// for the plain benchmark programs, which need no Google Benchmark. On a shared machine the wall
// time measures the load as well; the CPU time measures the work.
#include <sys/resource.h>

#include <chrono>
#include <cstdlib>
#include <string>

namespace bench {

struct Timing {
  double wall = 0, cpu = 0;  ///< seconds
};

inline double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// The run of `repeat` with the least wall time (its CPU time beside it).
template <class F>
Timing best_of(int repeat, F&& run) {
  Timing best{1e300, 0};
  for (int r = 0; r < repeat; ++r) {
    const double cpu0 = process_cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    run();
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (wall < best.wall) best = {wall, process_cpu_seconds() - cpu0};
  }
  return best;
}

/// The value after `--name` in argv, else `fallback`.
inline std::string option(int argc, char** argv, const std::string& name, const std::string& fallback) {
  for (int i = 1; i + 1 < argc; ++i)
    if (argv[i] == "--" + name) return argv[i + 1];
  return fallback;
}

inline bool flag(int argc, char** argv, const std::string& name) {
  for (int i = 1; i < argc; ++i)
    if (argv[i] == "--" + name) return true;
  return false;
}

}  // namespace bench
