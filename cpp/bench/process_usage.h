#pragma once
// The whole process's CPU time (user + system, every thread) and page faults over a benchmark's
// iterations, as counters beside Google Benchmark's wall time: on the shared machine the wall
// time mostly measures the load, these two measure the work (first touches show as faults and
// system time). Given the bytes one iteration outputs, also its page faults per output MB (a
// buffer touched once takes at most 256 per MB, one per 4 KB page; fewer with huge pages).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

class ProcessUsage {
 public:
  explicit ProcessUsage(benchmark::State& state, double output_bytes = 0.0) : state_(state), output_bytes_(output_bytes) {
    getrusage(RUSAGE_SELF, &start_);
  }
  /// The bytes one iteration outputs, when known only once it ran (a file's size).
  void set_output_bytes(double bytes) { output_bytes_ = bytes; }
  ~ProcessUsage() {
    rusage end{};
    getrusage(RUSAGE_SELF, &end);
    const double n = state_.iterations() ? static_cast<double>(state_.iterations()) : 1.0;
    const double faults = static_cast<double>(end.ru_minflt + end.ru_majflt - start_.ru_minflt - start_.ru_majflt) / n;
    state_.counters["faults"] = faults;
    if (output_bytes_ > 0.0) state_.counters["faults_per_mb"] = faults / (output_bytes_ / 1e6);
    state_.counters["cpu_ms"] = (seconds(end) - seconds(start_)) * 1e3 / n;
  }

 private:
  static double seconds(const rusage& u) {
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
  }
  benchmark::State& state_;
  double output_bytes_;
  rusage start_{};
};
