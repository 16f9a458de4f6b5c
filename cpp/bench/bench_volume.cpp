// Volumes: the seed's Table 2 (four volumetric renderers on a 100^3 3D RGB IFS with 5 maps)
// and the speed targets of PRR into an OpenVDB file (256^3, 512^3, 1024^3), 1 vs 2 threads,
// and the seed's real-time criterion (>= 10 volumes per second) at 128^3.
//
//   build/cpp/bench/bench_volume                                  # everything
//   build/cpp/bench/bench_volume --benchmark_filter=TableTwo      # Table 2 only
//   build/cpp/bench/bench_volume --benchmark_filter='PrrToVdb/1024'   # peak memory of 1024^3 alone
//   build/cpp/bench/bench_volume --benchmark_filter=AgainstDisk   # the .vdb writer against write + fsync
//
// Counters: voxels (occupied), depth, peak_rss_mb (the process's peak resident memory so far:
// run a size alone to read its own peak), and from process_usage.h faults, cpu_ms and
// faults_per_mb: the process's page faults per MB of the output (the file where one is written,
// else the volume's arrays). cpp/bench/vdb_vs_dd.py measures the writer against dd.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

#include "ifsforge/io/ifs_json.h"
#include "ifsforge/io/vdb.h"
#include "ifsforge/volume/volume_renderer.h"
#include "process_usage.h"

namespace {

using namespace ifsforge;

/// A system of samples/systems.
Ifs sample(const std::string& name) {
  std::string here = __FILE__;
  here = here.substr(0, here.rfind('/'));
  return read_ifs_json(here + "/../../samples/systems/" + name + ".json");
}

/// Table 2's system: the 5-map Sierpinski pyramid as a 3D + RGB (6D) IFS.
const Ifs& pyramid() {
  static const Ifs ifs = sample("volume_sierpinski_pyramid_rgb");
  return ifs;
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

double file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  return static_cast<double>(in.tellg());
}

/// The volume's arrays in memory: a key, a density and its channel means per voxel.
double volume_bytes(const Volume& v) {
  return static_cast<double>(v.size()) * (8.0 + 4.0 + 4.0 * v.channel_count());
}

/// The counters of every case but VdbWriterAgainstDisk (Google Benchmark's CSV report needs the
/// same in every row): the volume's, and the process's page faults per MB of `output` (the file
/// written, else the volume made).
void report(benchmark::State& state, const Volume& v, ProcessUsage& usage, double output) {
  state.counters["voxels"] = static_cast<double>(v.size());
  state.counters["depth"] = v.depth;
  state.counters["peak_rss_mb"] = peak_rss_mb();
  usage.set_output_bytes(output);
}

// Table 2: 100^3, each renderer with its defaults (occupancy-driven stopping rules).
void BM_TableTwo(benchmark::State& state, const char* algorithm) {
  VolumeOptions o;
  o.resolution = 100;
  Volume v;
  ProcessUsage usage(state);
  for (auto _ : state) v = render_volume(pyramid(), algorithm, o);
  report(state, v, usage, volume_bytes(v));
}
BENCHMARK_CAPTURE(BM_TableTwo, prr, "prr")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_TableTwo, ria, "ria")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(BM_TableTwo, dia, "dia")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(BM_TableTwo, eta, "eta")->Unit(benchmark::kMillisecond)->Iterations(2);

// The seed's own settings in Table 2: five levels of volume rewriting, escape bound 10.
void BM_TableTwoSeedSettings(benchmark::State& state, const char* algorithm) {
  VolumeOptions o;
  o.resolution = 100;
  o.depth = std::string(algorithm) == "dia" ? 5 : 0;
  o.escape_bound = std::string(algorithm) == "eta" ? 10 : 0;
  Volume v;
  ProcessUsage usage(state);
  for (auto _ : state) v = render_volume(pyramid(), algorithm, o);
  report(state, v, usage, volume_bytes(v));
}
BENCHMARK_CAPTURE(BM_TableTwoSeedSettings, dia_5_levels, "dia")->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK_CAPTURE(BM_TableTwoSeedSettings, eta_bound_10, "eta")->Unit(benchmark::kMillisecond)->Iterations(2);

// PRR into a .vdb file (render + OpenVDB write), all cores: the targets are 256^3 < 150 ms,
// 512^3 < 1 s, 1024^3 < 8 s with peak memory under 4 GB.
void BM_PrrToVdb(benchmark::State& state) {
  VolumeOptions o;
  o.resolution = static_cast<int>(state.range(0));
  const std::string path = "/tmp/ifsforge_bench_volume_" + std::to_string(getpid()) + ".vdb";
  VdbWriteOptions w;
  w.system = &pyramid();
  Volume v;
  ProcessUsage usage(state);
  for (auto _ : state) {
    v = render_volume(pyramid(), "prr", o);
    write_vdb(path, v, w);
  }
  report(state, v, usage, file_bytes(path));
  std::remove(path.c_str());
}
BENCHMARK(BM_PrrToVdb)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PrrToVdb)->Arg(512)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_PrrToVdb)->Arg(1024)->Unit(benchmark::kMillisecond)->Iterations(1);

// The OpenVDB write alone (grids, metadata, compression, atomic rename) of the PRR volume.
void BM_WriteVdb(benchmark::State& state) {
  VolumeOptions o;
  o.resolution = static_cast<int>(state.range(0));
  const Volume v = render_volume(pyramid(), "prr", o);
  const std::string path = "/tmp/ifsforge_bench_write_" + std::to_string(getpid()) + ".vdb";
  VdbWriteOptions w;
  w.system = &pyramid();
  ProcessUsage usage(state);
  for (auto _ : state) write_vdb(path, v, w);
  report(state, v, usage, file_bytes(path));
  std::remove(path.c_str());
}
BENCHMARK(BM_WriteVdb)->Arg(256)->Arg(512)->Unit(benchmark::kMillisecond);

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

long faults_so_far() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt + usage.ru_majflt;
}

double cpu_seconds_so_far() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The writer against the disk: write_vdb's MB/s (of output bytes) beside a plain write + fsync
// of the same bytes to the same folder, the writer's CPU time (every thread, user + system) per
// voxel and its page faults per output MB.
void BM_VdbWriterAgainstDisk(benchmark::State& state) {
  VolumeOptions o;
  o.resolution = static_cast<int>(state.range(0));
  const Volume v = render_volume(pyramid(), "prr", o);
  const std::string path = "/tmp/ifsforge_bench_disk_" + std::to_string(getpid()) + ".vdb";
  const std::string plain = path + ".plain";
  VdbWriteOptions w;
  w.system = &pyramid();
  double writer = 0.0, ceiling = 0.0, bytes = 0.0, faults = 0.0, cpu = 0.0;
  for (auto _ : state) {
    const long before = faults_so_far();
    const double cpu_before = cpu_seconds_so_far();
    auto start = std::chrono::steady_clock::now();
    write_vdb(path, v, w);
    writer += seconds_since(start);
    cpu += cpu_seconds_so_far() - cpu_before;
    faults += static_cast<double>(faults_so_far() - before);
    std::ifstream in(path, std::ios::binary);
    const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes += static_cast<double>(content.size());
    start = std::chrono::steady_clock::now();
    const int fd = ::open(plain.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    for (std::size_t at = 0; fd >= 0 && at < content.size();) {
      const ssize_t n = ::write(fd, content.data() + at, content.size() - at);
      if (n <= 0) break;
      at += static_cast<std::size_t>(n);
    }
    if (fd >= 0) ::fsync(fd), ::close(fd);
    ceiling += seconds_since(start);
  }
  state.counters["writer_mb_s"] = bytes / 1e6 / writer;
  state.counters["write_fsync_mb_s"] = bytes / 1e6 / ceiling;
  state.counters["faults_per_mb"] = faults / (bytes / 1e6);
  state.counters["cpu_ns_per_voxel"] = cpu * 1e9 / (static_cast<double>(v.size()) * static_cast<double>(state.iterations()));
  state.counters["mb"] = bytes / 1e6 / static_cast<double>(state.iterations());
  std::remove(path.c_str());
  std::remove(plain.c_str());
}
BENCHMARK(BM_VdbWriterAgainstDisk)->Arg(512)->Arg(1024)->Unit(benchmark::kMillisecond)->Iterations(2);

// Harder systems than the pyramid, at the gallery's resolutions: the 3D fern (thin, unequal
// contractions: deep and lopsided address trees) and the 6D coral (average-contractive only).
void BM_PrrSample(benchmark::State& state, const char* name, int resolution) {
  const Ifs ifs = sample(name);
  VolumeOptions o;
  o.resolution = resolution;
  Volume v;
  ProcessUsage usage(state);
  for (auto _ : state) v = render_volume(ifs, "prr", o);
  report(state, v, usage, volume_bytes(v));
}
BENCHMARK_CAPTURE(BM_PrrSample, fern_3d_192, "volume_fern_3d", 192)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PrrSample, coral_6d_128, "volume_coral_6d", 128)->Unit(benchmark::kMillisecond);

// Threads: the same 512^3 volume on 1 and on 2 threads (identical bytes, see the tests).
void BM_PrrThreads(benchmark::State& state) {
  VolumeOptions o;
  o.resolution = 512;
  o.threads = static_cast<int>(state.range(0));
  Volume v;
  ProcessUsage usage(state);
  for (auto _ : state) v = render_volume(pyramid(), "prr", o);
  report(state, v, usage, volume_bytes(v));
}
BENCHMARK(BM_PrrThreads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->Iterations(3);

// The seed's real-time criterion: at least 10 volumes per second at 128^3 (render only).
void BM_PrrRealTime(benchmark::State& state) {
  VolumeOptions o;
  o.resolution = 128;
  Volume v;
  ProcessUsage usage(state);
  for (auto _ : state) v = render_volume(pyramid(), "prr", o);
  state.SetItemsProcessed(state.iterations());
  report(state, v, usage, volume_bytes(v));
}
BENCHMARK(BM_PrrRealTime)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
