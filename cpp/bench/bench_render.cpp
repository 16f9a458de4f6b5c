// Render benchmarks against their targets: random iteration of the Barnsley fern into a
// 1024^2 density histogram (points/s on 1 and 2 threads), and point recursive rendering of
// the Sierpinski triangle at 4096^2, and the PNG writer (parallel strips). Counters: page faults and the process's CPU milliseconds
// (all threads) per iteration. Run: build/cpp/bench/bench_render
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>

#include "ifsforge/core/default_threads.h"
#include "ifsforge/io/png.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/render/tone_map.h"
#include "bench_systems.h"
#include "process_usage.h"

using namespace ifsforge;

namespace {

using bench::fern;
using bench::sierpinski;

/// Arg 0: threads; arg 1: points (1,024: the fixed cost of a render, framing and buffers).
void ChaosFern1024(benchmark::State& state) {
  const Ifs s = fern();
  RenderOptions o;
  o.iterations = static_cast<std::uint64_t>(state.range(1));
  o.threads = static_cast<int>(state.range(0));
  {
    ProcessUsage usage(state);
    for (auto _ : state) benchmark::DoNotOptimize(renderer("chaos").render(s, o));
  }
  state.counters["points/s"] = benchmark::Counter(double(o.iterations) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(ChaosFern1024)->Args({1, 200'000'000})->Args({2, 200'000'000})->Args({2, 1024})->Unit(benchmark::kMillisecond)->UseRealTime();

void ChaosTetrahedron3D(benchmark::State& state) {
  const Ifs s = sierpinski(3);
  RenderOptions o;
  o.iterations = 200'000'000;
  o.view = View{30, 20};
  o.threads = static_cast<int>(state.range(0));
  {
    ProcessUsage usage(state);
    for (auto _ : state) benchmark::DoNotOptimize(renderer("chaos").render(s, o));
  }
  state.counters["points/s"] = benchmark::Counter(double(o.iterations) * state.iterations(), benchmark::Counter::kIsRate);
}
BENCHMARK(ChaosTetrahedron3D)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

/// Arg 0: threads; arg 1: depth (0: automatic, pieces down to a pixel; 12: the seed's PRR at
/// the depth where the triangle's pieces reach one pixel, 3^12 leaves).
void PrrSierpinski4096(benchmark::State& state) {
  const Ifs s = sierpinski();
  RenderOptions o;
  o.width = o.height = 4096;
  o.threads = static_cast<int>(state.range(0));
  o.depth = static_cast<int>(state.range(1));
  ProcessUsage usage(state);
  for (auto _ : state) benchmark::DoNotOptimize(renderer("prr").render(s, o));
}
BENCHMARK(PrrSierpinski4096)->Args({1, 12})->Args({2, 12})->Args({1, 0})->Args({2, 0})->Unit(benchmark::kMillisecond)->UseRealTime();

/// Arg 0: size (the fern's density image, tone-mapped: what `render -o fern.png` encodes); arg 1:
/// threads. Counter: the file's bytes.
void WritePngFern(benchmark::State& state) {
  RenderOptions o;
  o.width = o.height = static_cast<int>(state.range(0));
  o.iterations = std::uint64_t(o.width) * o.height * 16;
  const Image image = tone_map(renderer("chaos").render(fern(), o));
  const std::string path = "/tmp/ifsforge_bench_fern.png";
  set_default_threads(static_cast<int>(state.range(1)));
  {
    ProcessUsage usage(state);
    for (auto _ : state) write_png(path, image);
  }
  set_default_threads(0);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  std::fseek(f, 0, SEEK_END);
  state.counters["bytes"] = double(std::ftell(f));
  std::fclose(f);
  std::remove(path.c_str());
}
BENCHMARK(WritePngFern)->Args({1024, 1})->Args({1024, 2})->Args({4096, 1})->Args({4096, 2})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
