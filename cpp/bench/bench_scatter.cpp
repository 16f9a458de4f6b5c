// The scatter ceiling beside the renderer: a plain loop of random increments over an image's
// counters (32-bit and 8-bit, uniformly random pixels) and the chaos game's fern, at 1024² to
// 8192², in points per CPU-second of one thread. Both fall as the image leaves the caches; the
// renderer's accumulation is measured against the naive loop in the same run. Then the
// random-iteration volume (ria) of the Sierpinski tetrahedron at 128³ to 1024³, whose voxels
// go into a hash table per thread, beside its own naive ceiling: random increments over an
// array of the table's size and type. A plain program.
//
//   build/cpp/bench/bench_scatter [--points 200000000] [--repeat 3] [--sizes 1024,2048,4096,8192]
//                                 [--volume-points 50000000] [--volume-sizes 128,512,1024]
//   /usr/bin/python3 cpp/bench/results.py bench_scatter --plain   # the same, written to RESULTS.md
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "bench_systems.h"
#include "bench_timing.h"
#include "ifsforge/render/renderer.h"
#include "ifsforge/volume/volume_renderer.h"

using namespace ifsforge;

namespace {

/// `points` increments of uniformly random counters among `cells` (a power of two), the
/// counters `stride` apart (splitmix64 draws).
template <class Counter>
std::uint64_t scatter(std::vector<Counter>& counters, std::uint64_t cells, std::size_t stride, std::uint64_t points) {
  const std::uint64_t mask = cells - 1;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (std::uint64_t i = 0; i < points; ++i) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    ++counters[((z ^ (z >> 31)) & mask) * stride];
  }
  std::uint64_t sum = 0;  // read back, so the loop is not dropped
  for (std::size_t i = 0; i < counters.size(); i += 4096) sum += counters[i];
  return sum;
}

/// Increments per CPU-second over `cells` counters `stride` apart (touched before the clock).
template <class Counter>
double scatter_rate(std::uint64_t cells, std::size_t stride, std::uint64_t points, int repeat) {
  std::vector<Counter> counters(cells * stride, 0);
  std::uint64_t sink = 0;
  const bench::Timing t = bench::best_of(repeat, [&] { sink += scatter(counters, cells, stride, points); });
  if (sink == 1) std::puts("");
  return double(points) / t.cpu;
}

/// The slots of the tetrahedron's voxel table (4 words each) once it holds `voxels` voxels: the
/// table's rule (volume/voxel_table.h), powers of two from 4096, at most 3/4 full.
std::uint64_t table_slots(std::size_t voxels) {
  std::uint64_t slots = 4096;
  while (4 * voxels > 3 * slots) slots *= 2;
  return slots;
}

/// CPU seconds of the fern's chaos game; `tiles` false: large images counted point by point as
/// they come (IFSFORGE_CHAOS_TILES=0), for the comparison.
double chaos_seconds(int size, std::uint64_t points, int repeat, bool tiles) {
  setenv("IFSFORGE_CHAOS_TILES", tiles ? "1" : "0", 1);
  RenderOptions o;
  o.width = o.height = size;
  o.iterations = points;
  o.threads = 1;
  const bench::Timing t = bench::best_of(repeat, [&] { (void)renderer("chaos").render(bench::fern(), o); });
  unsetenv("IFSFORGE_CHAOS_TILES");
  return t.cpu;
}

/// CPU seconds and occupied voxels of the tetrahedron's random-iteration volume; `bins` false:
/// every point added to the voxel table as it comes (IFSFORGE_VOXEL_BINS=0), for the comparison.
double volume_seconds(int resolution, std::uint64_t points, int repeat, bool bins, std::size_t& voxels) {
  setenv("IFSFORGE_VOXEL_BINS", bins ? "1" : "0", 1);
  VolumeOptions o;
  o.resolution = resolution;
  o.iterations = points;
  o.threads = 1;
  static const Ifs tetrahedron = bench::sierpinski(3);
  const bench::Timing t = bench::best_of(repeat, [&] { voxels = render_volume(tetrahedron, "ria", o).size(); });
  unsetenv("IFSFORGE_VOXEL_BINS");
  return t.cpu;
}

std::vector<int> size_list(int argc, char** argv, const char* name, const char* fallback) {
  std::vector<int> sizes;
  std::stringstream list(bench::option(argc, argv, name, fallback));
  for (std::string item; std::getline(list, item, ',');) sizes.push_back(std::stoi(item));
  return sizes;
}

}  // namespace

int main(int argc, char** argv) {
  if (bench::flag(argc, argv, "help")) {
    std::puts("bench_scatter [--points P (2e8)] [--repeat R (3)] [--sizes 1024,2048,4096,8192] [--volume-points P "
              "(5e7)] [--volume-sizes 128,512,1024]");
    return 0;
  }
  const auto points = static_cast<std::uint64_t>(std::stod(bench::option(argc, argv, "points", "2e8")));
  const int repeat = std::stoi(bench::option(argc, argv, "repeat", "3"));
  const std::vector<int> sizes = size_list(argc, argv, "sizes", "1024,2048,4096,8192");
  const auto volume_points = static_cast<std::uint64_t>(std::stod(bench::option(argc, argv, "volume-points", "5e7")));
  const std::vector<int> volume_sizes = size_list(argc, argv, "volume-sizes", "128,512,1024");

  std::printf("Millions of points per CPU-second, one thread, %.3g points per run, best of %d. Scatter: "
              "increments of uniformly random counters. Chaos: the fern's render, whole (framing, "
              "buffers and finish included) or marginal (less a 1,024-point render's CPU time: the "
              "cost of the points), its counts made point by point (direct) or through tiles (the "
              "default from 4096^2 pixels).\n\n",
              double(points), repeat);
  std::printf("| image | scatter 32-bit | scatter 8-bit | chaos fern, whole render | chaos marginal, direct "
              "counts | chaos marginal, default | default / scatter 32-bit |\n| --- | ---: | ---: | ---: | ---: | ---: "
              "| ---: |\n");
  for (int size : sizes) {
    if (size <= 0 || (size & (size - 1))) {
      std::fprintf(stderr, "bench_scatter: sizes are powers of two (%d)\n", size);
      return 2;
    }
    const std::uint64_t pixels = std::uint64_t(size) * size;
    const double wide = scatter_rate<std::uint32_t>(pixels, 1, points, repeat);
    const double narrow = scatter_rate<std::uint8_t>(pixels, 1, points, repeat);
    // The render's own fixed cost (framing, buffers, the finish over every pixel) measured with
    // 1,024 points and taken out: the marginal rate is the cost of a point.
    const double fixed = chaos_seconds(size, 1024, repeat, true);
    const double direct = chaos_seconds(size, points, repeat, false), tiled = chaos_seconds(size, points, repeat, true);
    auto rate = [&](double seconds) { return double(points) / std::max(seconds - fixed, 1e-9) / 1e6; };
    std::printf("| %d² | %.0f M | %.0f M | %.0f M | %.0f M | %.0f M | %.2f× |\n", size, wide / 1e6, narrow / 1e6,
                double(points) / tiled / 1e6, rate(direct), rate(tiled), rate(tiled) * 1e6 / wide);
    std::fflush(stdout);
  }
  std::printf("\nThe random-iteration volume (ria) of the Sierpinski tetrahedron, %.3g points per run, one "
              "thread, best of %d: millions of points per CPU-second, whole (grid, tables, merge and volume "
              "included) and marginal (less a 1,024-point render's CPU time), each point added to the voxel "
              "table as it comes (direct) or as the default does (the chain lanes, where the CPU has them: "
              "batches added directly; else through bins by region for tables of 4 MB or more); the naive "
              "ceiling: as many increments of random 32-byte slots of a table's size (the "
              "slots the tetrahedron's table ends with), in the same run.\n\n| volume | voxels | table | "
              "naive scatter | whole, direct | whole, default | marginal, direct | marginal, default | "
              "default (whole) / naive |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n",
              double(volume_points), repeat);
  for (int resolution : volume_sizes) {
    std::size_t voxels = 0;
    const double fixed = volume_seconds(resolution, 1024, repeat, true, voxels);
    const double direct = volume_seconds(resolution, volume_points, repeat, false, voxels);
    const double binned = volume_seconds(resolution, volume_points, repeat, true, voxels);
    // The naive ceiling: a 64-bit word incremented in uniformly random 32-byte slots of the table's size.
    const std::uint64_t slots = table_slots(voxels);
    const double naive = scatter_rate<std::uint64_t>(slots, 4, volume_points, repeat) / 1e6;
    auto rate = [&](double seconds) { return double(volume_points) / std::max(seconds, 1e-9) / 1e6; };
    std::printf("| %d³ | %zu | %.0f MB | %.1f M | %.1f M | %.1f M | %.1f M | %.1f M | %.2f× |\n", resolution, voxels,
                double(slots) * 32 / 1e6, naive, rate(direct), rate(binned), rate(direct - fixed), rate(binned - fixed),
                rate(binned) / naive);
    std::fflush(stdout);
  }
  return 0;
}
