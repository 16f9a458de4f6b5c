// The rendering-algorithm catalogue at the seed's reference size (5.13.1: a 1000 x 1000 binary
// image of a 5-map IFS): time and operation count of every chapter-5 algorithm.
// Targets: every deterministic algorithm except escape time < 100 ms, escape time < 2 s,
// image-based rendering < 50 ms. Run: build/cpp/bench/bench_algorithms [--benchmark_filter=...]
// The "ops" counter is the algorithm's own operation count (Raster::points; see each
// renderer's documentation), printed beside the seed's estimate "seed_ops".
#include <benchmark/benchmark.h>

#include <string>

#include "ifsforge/render/renderer.h"

using namespace ifsforge;

namespace {

/// The Vicsek cross: five copies at a third of the size (centre and corners), just touching,
/// no rotation: non-overlapping, linear, hyperbolic, as 5.13.1 assumes, and a tile system, so
/// that every algorithm (AFRA too) applies.
Ifs vicsek() {
  std::vector<AffineMap> maps;
  const double t = 1.0 / 3.0;
  const double offsets[5][2] = {{0, 0}, {2 * t, 0}, {t, t}, {0, 2 * t}, {2 * t, 2 * t}};
  for (const auto& o : offsets) maps.emplace_back(2, std::vector<double>{t, 0, 0, t}, std::vector<double>{o[0], o[1]});
  return Ifs("vicsek", ChannelLayout("xy"), maps, std::vector<double>(5, 1.0));
}

void render_algorithm(benchmark::State& state, const std::string& name, bool binary) {
  const Ifs system = vicsek();
  RenderOptions o;
  o.width = o.height = 1000;
  o.window = Window{-0.01, -0.01, 1.01, 1.01};
  o.binary = binary;
  o.threads = static_cast<int>(state.range(0));
  const Renderer& r = renderer(name);
  std::uint64_t ops = 0, covered = 0;
  for (auto _ : state) {
    const Raster raster = r.render(system, o);
    ops = raster.points;
    covered = raster.covered();
    benchmark::DoNotOptimize(raster.density.data());
  }
  state.counters["ops"] = static_cast<double>(ops);
  state.counters["covered"] = static_cast<double>(covered);
  const double seed_ops = seed_reference(name).operations;  // 5.13.1's estimate, kept on the registry
  if (seed_ops > 0) state.counters["seed_ops"] = seed_ops;
}

const bool registered = [] {
  for (const Renderer* r : renderers()) {
    if (r->name() == "color-stealing") continue;  // needs a picture; same work as chaos
    benchmark::RegisterBenchmark(("Algorithm1000/" + r->name()).c_str(), render_algorithm, r->name(), true)
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  // The mass algorithms' default (not binary: spread=box, a measure).
  for (const char* name : {"cma", "photocopy"})
    benchmark::RegisterBenchmark((std::string("Spread1000/") + name).c_str(), render_algorithm, name, false)
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  return true;
}();

}  // namespace

BENCHMARK_MAIN();
