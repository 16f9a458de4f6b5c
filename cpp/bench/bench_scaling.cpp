// The thread sweep: each parallel path of the library on 1, 2, 4, ... threads up to the
// machine's cores (best of a few runs each), printed as a Markdown table with each path's 1-to-2
// speed-up and its serial fraction (Amdahl's law fitted to the sweep). A plain program (no Google
// Benchmark) whose systems are built in code, so it runs on another x86-64 machine with only the
// shared libraries libifsforge needs.
//
// Then each path's serial share, steadily, and the PIFS encoder's for three encodes: each row
// run --serial-runs times on 2 threads alternating with 1-thread runs, the median and spread of
// the share from each 2-thread run's own CPU and wall time (single runs drift with the machine's
// speed), and beside it the part the threads slept (the code's) apart from their wait for a CPU
// (the machine's).
//
//   build/cpp/bench/bench_scaling [--threads 16] [--repeat 3 (0: no sweep)] [--points 1000000000]
//                                 [--only chaos,prr-sierpinski-serial,pifs-serial]
//                                 [--serial-runs 10] [--serial-encodes 512-gray,1024-gray,2048-colour]
//   /usr/bin/python3 cpp/bench/results.py bench_scaling --plain   # the same, written to RESULTS.md
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "bench_systems.h"
#include "bench_timing.h"
#include "thread_schedule.h"
#include "ifsforge/core/image.h"
#include "ifsforge/io/vdb.h"
#include "ifsforge/pifs/encoder.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_renderer.h"

using namespace ifsforge;

namespace {

struct Path {
  std::string key, label;
  std::function<void(int threads)> run;
  /// Its runs in the paths' serial-share table: this share of --serial-runs (at least 3), less
  /// for the long paths.
  double serial_runs = 1.0;
  /// Set: done before each run, untimed.
  std::function<void()> before = nullptr;
};

/// A photograph-like 8-bit texture (octaves of sines plus hashed noise, each channel's phase
/// shifted) for the encoder.
Image texture(int size, int channels = 1) {
  Image im(size, size, channels);
  for (int c = 0; c < channels; ++c)
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        std::uint32_t h = std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u ^ std::uint32_t(c) * 83492791u;
        h = (h ^ (h >> 13)) * 0x5bd1e995u;
        double v = 0.5 + 0.06 * (double(h >> 8 & 0xFFFF) / 65535.0 - 0.5);
        for (int o = 0; o < 5; ++o)
          v += 0.18 / (o + 1) * std::sin(x * 0.0065 * (1 << o) + o + c) * std::cos(y * 0.0055 * (1 << o) - o);
        im.at(x, y, c) = float(std::round(std::clamp(v, 0.0, 1.0) * 255.0) / 255.0);
      }
  return im;
}

/// The encode every PIFS row times: 50:1 on `threads` threads.
void encode(const Image& image, int threads) {
  PifsEncodeOptions o;
  o.ratio = 50;
  o.threads = threads;
  (void)pifs_encode(image, o);
}

/// The .vdb path's file: in the temporary folder, named by the process (main removes it).
std::string vdb_path() {
  const char* folder = std::getenv("TMPDIR");
  return std::string(folder && *folder ? folder : "/tmp") + "/ifsforge_bench_scaling_" + std::to_string(getpid()) +
         ".vdb";
}

std::vector<Path> paths(std::uint64_t points) {
  auto image = [](const char* algorithm, Ifs ifs, int size, std::uint64_t iterations) {
    return [=](int threads) {
      RenderOptions o;
      o.width = o.height = size;
      o.iterations = iterations;
      o.threads = threads;
      (void)renderer(algorithm).render(ifs, o);
    };
  };
  const std::string billions = std::to_string(double(points) / 1e9).substr(0, 4);
  std::vector<Path> all = {
      {"chaos", "chaos, fern 1024², " + billions + "·10⁹ points", image("chaos", bench::fern(), 1024, points), 0.5},
      {"prr-fern", "PRR fern 4096²", image("prr", bench::fern(), 4096, 0), 0.3},
      {"prr-sierpinski", "PRR Sierpinski 4096²", image("prr", bench::sierpinski(), 4096, 0)},
      {"volume", "volume PRR 512³ (tetrahedron, render)",
       [](int threads) {
         VolumeOptions o;
         o.resolution = 512;
         o.threads = threads;
         (void)render_volume(bench::sierpinski(3), "prr", o);
       }},
      // The row: the band writer's jobs are the grid's bands (128 rows of x each).
      {"vdb", "volume PRR 1024³ render + `.vdb` write (tetrahedron)",
       [file = vdb_path()](int threads) {
         VolumeOptions o;
         o.resolution = 1024;
         o.threads = threads;
         VdbWriteOptions w;
         w.threads = threads;
         (void)render_volume_to_vdb(file, bench::sierpinski(3), "prr", o, w);
       }},
      {"pifs", "PIFS encode 1024² gray", [im = texture(1024)](int threads) { encode(im, threads); }},
  };
  // Each .vdb run writes a new file: the last run's is removed before it and the disk synced,
  // untimed (a file replaced by the write's rename frees its blocks then, 2-15 ms on this
  // machine's ext4 mounted `discard`, against 0.05 ms for a new name: the disk's, not the writer's).
  for (Path& path : all)
    if (path.key == "vdb") path.before = [file = vdb_path()] {
        std::remove(file.c_str());
        sync();
      };
  return all;
}

/// 1, 2, 4, ... below `cores`, then `cores`.
std::vector<int> sweep(int cores) {
  std::vector<int> counts;
  for (int n = 1; n < cores; n *= 2) counts.push_back(n);
  counts.push_back(cores);
  return counts;
}

/// Amdahl's law T(n) = T1 (s + (1 - s) / n) fitted by least squares as T = a + b / n: the serial
/// fraction s = a / (a + b).
double serial_fraction(const std::vector<int>& threads, const std::vector<double>& seconds) {
  const std::size_t n = threads.size();
  if (n < 2) return NAN;
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += 1.0 / threads[i] / n;
    my += seconds[i] / n;
  }
  double sxy = 0, sxx = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxy += (1.0 / threads[i] - mx) * (seconds[i] - my);
    sxx += (1.0 / threads[i] - mx) * (1.0 / threads[i] - mx);
  }
  const double b = sxy / sxx, a = my - b * mx;
  return a / (a + b);
}

/// A run on n threads that took `wall` seconds and `cpu` CPU seconds in all: were its serial part
/// s of the work, wall = s cpu + (1 - s) cpu / n, so s = (n wall - cpu) / ((n - 1) cpu). Idle
/// waits and imbalance count as serial, as they cost the same on more cores.
double serial_from_cpu(int n, double wall, double cpu) {
  return n < 2 || cpu <= 0 ? NAN : (n * wall - cpu) / ((n - 1) * cpu);
}

std::string seconds_cell(double s) {
  char text[32];
  std::snprintf(text, sizeof text, s < 1 ? "%.3f" : "%.2f", s);
  return text;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// A row of a serial-share table: `runs` runs of `run` on 2 threads, each after one on 1, each run
/// after `before` (if set, untimed).
struct SerialRow {
  std::string label;
  std::function<void(int threads)> run;
  int runs;
  std::function<void()> before = nullptr;
};

/// The fastest of `repeat` runs of `run` on `threads` threads, each after `before` (untimed).
bench::Timing best_run(int repeat, const std::function<void(int)>& run, const std::function<void()>& before,
                       int threads) {
  bench::Timing best{1e300, 0};
  for (int r = 0; r < repeat; ++r) {
    if (before) before();
    const bench::Timing t = bench::best_of(1, [&] { run(threads); });
    if (t.wall < best.wall) best = t;
  }
  return best;
}

/// The serial share on 2 threads of each row, `row.runs` runs on 2 threads each after one on 1
/// (so both see the same drift of the machine's speed): the median, quartiles and range of the
/// share serial_from_cpu gives each 2-thread run, the median idle thread time (2 wall − CPU: a
/// core waiting, for work or for the machine) of those runs and the median CPU of both counts.
/// Beside it the code's own part of that idle time (thread_schedule.h): the threads' sleep,
/// 2 wall − run − waiting for a CPU, as a share of their run time, and the waiting apart.
/// `intro` heads the table, `first_column` names its rows.
void serial_share_table(const std::string& intro, const char* first_column, const std::vector<SerialRow>& rows) {
  std::printf("\n%s serial share on 2 threads, each run after a 1-thread run: median, "
              "quartiles and range of (2 wall - CPU) / CPU per run; idle: 2 wall - CPU (thread-ms a core waited), "
              "median; CPU: median per %s on 1 and 2 threads.\n\n"
              "Slept: the threads' sleep waiting for work, (2 wall - run - waiting) / run from the kernel's "
              "per-thread run time and run-queue wait (the code's serial part without the machine's; the "
              "calling thread's wall - run - waiting plus the other threads' wall less theirs, at least 0); "
              "waited: the run-queue wait, ms (the machine's part).\n\n"
              "| %s | runs | serial median | quartiles | range | idle ms | slept median | slept range | "
              "waited ms | CPU s, 1 thread | CPU s, 2 threads |\n"
              "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
              intro.c_str(), first_column, first_column);
  for (const SerialRow& row : rows) {
    std::vector<double> share, idle, slept, waited, cpu1, cpu2;
    for (int r = 0; r < row.runs; ++r) {
      cpu1.push_back(best_run(1, row.run, row.before, 1).cpu);
      if (row.before) row.before();
      const bench::ThreadSchedule before = bench::thread_schedule();
      const bench::Timing t = bench::best_of(1, [&] { row.run(2); });
      const bench::ThreadSchedule after = bench::thread_schedule();
      share.push_back(serial_from_cpu(2, t.wall, t.cpu));
      idle.push_back(2 * t.wall - t.cpu);
      const double run = after.run - before.run, waiting = after.waiting - before.waiting;
      slept.push_back(after.known && run > 0 ? bench::workers_slept(before, after, 2, t.wall) / run : NAN);
      waited.push_back(waiting);
      cpu2.push_back(t.cpu);
    }
    const auto quantile = [](std::vector<double> v, double q) {
      std::sort(v.begin(), v.end());
      return v[std::size_t(std::lround(q * double(v.size() - 1)))];
    };
    std::printf("| %s | %d | %.1f%% | %.1f–%.1f%% | %.1f–%.1f%% | %.1f | %.1f%% | %.1f–%.1f%% | %.1f | %s | %s |\n",
                row.label.c_str(), row.runs, 100 * median(share), 100 * quantile(share, 0.25),
                100 * quantile(share, 0.75), 100 * quantile(share, 0), 100 * quantile(share, 1), 1e3 * median(idle),
                100 * median(slept), 100 * quantile(slept, 0), 100 * quantile(slept, 1), 1e3 * median(waited),
                seconds_cell(median(cpu1)).c_str(), seconds_cell(median(cpu2)).c_str());
    std::fflush(stdout);
  }
}

/// The PIFS encoder's serial share (serial_share_table): `runs` runs of each encode (the 2048²
/// colour one, about 70× the 512² one's CPU, half as many, at least 3). `keys` chooses the
/// encodes (512-gray, 1024-gray, 2048-colour; empty: all).
void pifs_serial_table(int runs, const std::string& keys) {
  struct Encode {
    const char* key;
    const char* label;
    int size, channels, runs;
  };
  const Encode encodes[] = {{"512-gray", "512² gray", 512, 1, runs},
                            {"1024-gray", "1024² gray", 1024, 1, runs},
                            {"2048-colour", "2048² colour", 2048, 3, std::max(3, runs / 2)}};
  std::vector<SerialRow> rows;
  for (const Encode& e : encodes) {
    if (!keys.empty() && ("," + keys + ",").find("," + std::string(e.key) + ",") == std::string::npos) continue;
    rows.push_back({e.label, [image = texture(e.size, e.channels)](int threads) { encode(image, threads); }, e.runs});
  }
  serial_share_table("PIFS encode (50:1)", "encode", rows);
}

}  // namespace

int main(int argc, char** argv) {
  if (bench::flag(argc, argv, "help")) {
    std::puts("bench_scaling [--threads N (default: the machine's cores)] [--repeat R (3)] "
              "[--repeat 0: no sweep, the serial-share tables alone] "
              "[--points P (chaos game points, 1e9)] [--only key,key (chaos, prr-fern, prr-sierpinski, volume, vdb, "
              "pifs; key-serial, e.g. pifs-serial: that path's serial-share row alone)] "
              "[--serial-runs N (10; the serial-share tables' runs per row, 0: none)] "
              "[--serial-encodes key,key (512-gray, 1024-gray, 2048-colour; default all)]");
    return 0;
  }
  const int cores = std::stoi(bench::option(argc, argv, "threads",
                                            std::to_string(std::max(1u, std::thread::hardware_concurrency()))));
  const int repeat = std::stoi(bench::option(argc, argv, "repeat", "3"));
  const auto points = static_cast<std::uint64_t>(std::stod(bench::option(argc, argv, "points", "1e9")));
  const std::string only = bench::option(argc, argv, "only", "");
  const int serial_runs = std::stoi(bench::option(argc, argv, "serial-runs", "10"));
  const std::vector<int> counts = sweep(cores);
  const auto chosen = [&](const std::string& key) { return ("," + only + ",").find("," + key + ",") != std::string::npos; };
  const std::vector<Path> all = paths(points);

  if (repeat > 0) {
    std::printf("Seconds (wall, best of %d) per thread count; CPU s: the process's CPU seconds of the run on %d "
                "threads; serial: the serial fraction of Amdahl's law fitted to the row; serial (CPU): the same "
                "fraction from that one run's CPU and wall time, (N wall - CPU) / ((N - 1) CPU) on N threads, which "
                "a slow one-thread run cannot skew.\n\n| path |",
                repeat, counts.back());
    for (int n : counts) std::printf(" %d |", n);
    std::printf(" %d vs 1 | 1→2 | serial | serial (CPU) | CPU s at %d |\n| --- |", counts.back(), counts.back());
    for (std::size_t i = 0; i < counts.size() + 5; ++i) std::printf(" ---: |");
    std::printf("\n");
  }
  for (const Path& path : all) {
    if (repeat <= 0 || (!only.empty() && !chosen(path.key))) continue;
    std::vector<double> wall;
    double cpu = 0;
    for (int n : counts) {
      const bench::Timing t = best_run(repeat, path.run, path.before, n);
      wall.push_back(t.wall);
      cpu = t.cpu;
    }
    std::printf("| %s |", path.label.c_str());
    for (double s : wall) std::printf(" %s |", seconds_cell(s).c_str());
    const double two = counts.size() > 1 ? wall[0] / wall[1] : NAN;
    std::printf(" %.1f× | %.2f× | %.1f%% | %.1f%% | %s |\n", wall[0] / wall.back(), two,
                100.0 * serial_fraction(counts, wall), 100.0 * serial_from_cpu(counts.back(), wall.back(), cpu),
                seconds_cell(cpu).c_str());
    std::fflush(stdout);
  }
  // Every path but the PIFS encode (the table below has it) split as the PIFS table splits it.
  std::vector<SerialRow> rows;
  for (const Path& path : all)
    if (serial_runs > 0 && path.key != "pifs" && (only.empty() || chosen(path.key) || chosen(path.key + "-serial")))
      rows.push_back({path.label, path.run, std::max(3, int(std::lround(serial_runs * path.serial_runs))), path.before});
  if (!rows.empty()) serial_share_table("Each path's", "path", rows);
  if (serial_runs > 0 && (only.empty() || chosen("pifs") || chosen("pifs-serial")))
    pifs_serial_table(serial_runs, bench::option(argc, argv, "serial-encodes", ""));
  std::remove(vdb_path().c_str());
  return 0;
}
