// The speed targets of fractal interpolation, palettes and terrains:
//   a 1000 x 1000 regular terrain < 30 ms and a 4096 x 4096 one < 0.5 s (both cores),
//   a 4096-entry palette < 1 ms, a 1024^2 terrain mesh written as .glb < 0.5 s.
// Run: build/cpp/bench/bench_terrain [--benchmark_filter=...]
// Counters (process_usage.h): the process's page faults per iteration and per MB of the output
// (heights, u and v; the image; the mesh's arrays; the file), and its CPU milliseconds.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "ifsforge/interpolation/fractal_interpolation.h"
#include "ifsforge/terrain/height_image.h"
#include "ifsforge/terrain/terrain.h"
#include "ifsforge/terrain/terrain_controls.h"
#include "ifsforge/io/terrain_mesh_file.h"
#include "ifsforge/interpolation/vertical_scaling.h"
#include "ifsforge/texture/palette.h"
#include "process_usage.h"

using namespace ifsforge;

namespace {

/// 10 x 10 random controls: 9 intervals divide both 999 and 4095, so every control is a sample.
TerrainControls controls(TerrainGrid grid = TerrainGrid::Regular) {
  TerrainControls c;
  c.grid = grid;
  c.heights = random_heights(grid, 10, 10, {0.5}, 0.5, 1);
  c.a22_u = vertical_scaling(9, 0.4, SignPattern::Random, 1, 1);
  c.a22_v = vertical_scaling(9, 0.35, SignPattern::Random, 1, 2);
  if (grid == TerrainGrid::Irregular) random_shifts(c, 0.3, 2);
  return c;
}

PaletteSpec earth() {
  PaletteSpec s;
  s.stops = {{0.06, 0.16, 0.36}, {0.16, 0.40, 0.58}, {0.80, 0.74, 0.52}, {0.28, 0.50, 0.20},
             {0.16, 0.34, 0.12}, {0.48, 0.38, 0.26}, {0.58, 0.55, 0.52}, {0.97, 0.97, 0.99}};
  s.a22 = {std::vector<double>{0.3}, std::vector<double>{-0.3}, std::vector<double>{0.25}};
  return s;
}

void RegularTerrain(benchmark::State& state) {
  const int n = int(state.range(0)), threads = int(state.range(1));
  const TerrainControls c = controls();
  const ProcessUsage usage(state, 4.0 * n * n);  // the heights: one float per sample
  for (auto _ : state) benchmark::DoNotOptimize(make_terrain(c, n, n, threads).heights.data());
  state.counters["samples/s"] = benchmark::Counter(double(n) * n, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(RegularTerrain)->Args({1000, 2})->Args({1000, 1})->Args({4096, 2})->Args({4096, 1})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

void IrregularTerrain(benchmark::State& state) {
  const int n = int(state.range(0));
  const TerrainControls c = controls(TerrainGrid::Irregular);
  const ProcessUsage usage(state, 12.0 * n * n);  // heights, u and v: three floats per sample
  for (auto _ : state) benchmark::DoNotOptimize(make_terrain(c, n, n, 2).heights.data());
}
BENCHMARK(IrregularTerrain)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

void HeightImageIrregular(benchmark::State& state) {
  const int n = int(state.range(0));
  const Terrain t = make_terrain(controls(TerrainGrid::Irregular), n, n, 2);
  ProcessUsage usage(state);
  std::size_t bytes = 0;
  for (auto _ : state) {
    const Image image = height_image(t, n, n, 2);
    bytes = image.pixels.size() * sizeof(float);
    benchmark::DoNotOptimize(image.pixels.data());
  }
  usage.set_output_bytes(double(bytes));
}
BENCHMARK(HeightImageIrregular)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

void Palette4096(benchmark::State& state) {
  const PaletteSpec spec = earth();
  for (auto _ : state) benchmark::DoNotOptimize(make_palette(spec, std::size_t(state.range(0))).colors.data());
}
BENCHMARK(Palette4096)->Arg(4096)->Unit(benchmark::kMicrosecond);

void FractalInterpolationSample(benchmark::State& state) {
  const FractalInterpolation f({0, 1, 2, 3, 4}, {0.0, 1.0, 0.35, 0.8, 0.1}, {0.6, -0.5, 0.7, -0.4});
  for (auto _ : state) benchmark::DoNotOptimize(f.sample(std::size_t(state.range(0))).data());
}
BENCHMARK(FractalInterpolationSample)->Arg(4096)->Arg(1 << 20)->Unit(benchmark::kMicrosecond);

void TerrainMesh1024(benchmark::State& state) {
  const Terrain t = make_terrain(controls(), 1024, 1024, 2);
  ProcessUsage usage(state);
  std::size_t bytes = 0;
  for (auto _ : state) {
    const TriangleMesh mesh = terrain_mesh(t, {}, 2);
    bytes = mesh.positions.size() * 12 + mesh.normals.size() * 12 + mesh.colors.size() * 16 + mesh.uvs.size() * 8 +
            mesh.triangles.size() * 12;
    benchmark::DoNotOptimize(mesh.positions.data());
  }
  usage.set_output_bytes(double(bytes));
}
BENCHMARK(TerrainMesh1024)->Unit(benchmark::kMillisecond)->UseRealTime();

void WriteGlb1024(benchmark::State& state) {
  const Terrain t = make_terrain(controls(), 1024, 1024, 2);
  TerrainMeshOptions o;
  o.palette = make_palette(earth(), 256);
  const std::string path = (std::filesystem::temp_directory_path() / "ifsforge_bench_terrain.glb").string();
  ProcessUsage usage(state);
  for (auto _ : state) write_terrain_mesh(path, t, o, 2);
  usage.set_output_bytes(double(std::filesystem::file_size(path)));
  state.counters["MB"] = double(std::filesystem::file_size(path)) / 1e6;
  std::filesystem::remove(path);
}
BENCHMARK(WriteGlb1024)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
