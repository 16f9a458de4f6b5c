#pragma once
// The whole process's CPU time (user + system, every thread) and page faults over a benchmark's
// iterations, as counters beside Google Benchmark's wall time: on the shared machine the wall
// time mostly measures the load, these two measure the work (first touches show as faults and
// system time).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

class ProcessUsage {
 public:
  explicit ProcessUsage(benchmark::State& state) : state_(state) { getrusage(RUSAGE_SELF, &start_); }
  ~ProcessUsage() {
    rusage end{};
    getrusage(RUSAGE_SELF, &end);
    const double n = state_.iterations() ? static_cast<double>(state_.iterations()) : 1.0;
    state_.counters["faults"] = static_cast<double>(end.ru_minflt + end.ru_majflt - start_.ru_minflt - start_.ru_majflt) / n;
    state_.counters["cpu_ms"] = (seconds(end) - seconds(start_)) * 1e3 / n;
  }

 private:
  static double seconds(const rusage& u) {
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  benchmark::State& state_;
  rusage start_{};
};
