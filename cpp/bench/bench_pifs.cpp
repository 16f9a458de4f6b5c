// The speed targets of fractal compression on two cores: encoding 512² gray < 0.2 s, 512²
// colour < 0.4 s, 2048² colour < 5 s; decoding on 2 threads never slower than on 1. Rows on 1
// and 2 threads give the parallel share (CPU time of 2 threads against the wall).
// The image is a PNG named by IFSFORGE_PIFS_IMAGE (e.g. skimage's camera saved as PNG), else a
// synthetic photograph-like texture (several octaves of sines plus hashed noise); 2048² rows
// tile it 4×4.
// Run: build/cpp/bench/bench_pifs [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include "process_usage.h"

#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "ifsforge/io/png.h"
#include "ifsforge/pifs/decoder.h"
#include "ifsforge/pifs/encoder.h"

using namespace ifsforge;

namespace {

Image test_image(int channels) {
  if (const char* path = std::getenv("IFSFORGE_PIFS_IMAGE")) {
    Image png = read_png(path);
    if (png.channels == channels && png.width == 512 && png.height == 512) return png;
  }
  Image im(512, 512, channels);
  for (int y = 0; y < 512; ++y)
    for (int x = 0; x < 512; ++x)
      for (int c = 0; c < channels; ++c) {
        std::uint32_t h = std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u ^ std::uint32_t(c) * 83492791u;
        h = (h ^ (h >> 13)) * 0x5bd1e995u;
        const double noise = double(h >> 8 & 0xFFFF) / 65535.0 - 0.5;
        double v = 0.5;
        for (int o = 0; o < 5; ++o)
          v += 0.18 / (o + 1) * std::sin(x * 0.013 * (1 << o) + c + o) * std::cos(y * 0.011 * (1 << o) - o);
        im.at(x, y, c) = float(std::fmin(1.0, std::fmax(0.0, v + 0.06 * noise)));
      }
  return im;
}

Image tiled(const Image& im, int times) {
  Image out(im.width * times, im.height * times, im.channels);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x)
      for (int c = 0; c < im.channels; ++c) out.at(x, y, c) = im.at(x % im.width, y % im.height, c);
  return out;
}

PifsEncodeOptions options(int threads) {
  PifsEncodeOptions o;
  o.ratio = 50;
  o.threads = threads;
  return o;
}

// Arguments: (channels, side, threads).
void Encode(benchmark::State& state) {
  const Image small = test_image(int(state.range(0)));
  const Image im = state.range(1) == 512 ? small : tiled(small, int(state.range(1) / 512));
  // The same counters as Decode512's: a CSV report needs every counter in every row.
  const double side = double(state.range(1));
  const ProcessUsage usage(state, side * side * double(state.range(0)) * 4.0);  // the planes: a float per sample
  for (auto _ : state) benchmark::DoNotOptimize(pifs_encode(im, options(int(state.range(2)))));
}
// Arguments: (channels, scale, threads).
void Decode512(benchmark::State& state) {
  const PifsCode code = pifs_encode(test_image(int(state.range(0))), options(2));
  PifsDecodeOptions d;
  d.scale = double(state.range(1));
  d.threads = int(state.range(2));
  const double side = 512.0 * double(state.range(1));
  const ProcessUsage usage(state, side * side * double(state.range(0)) * 4.0);  // the planes: a float per sample
  for (auto _ : state) benchmark::DoNotOptimize(pifs_decode(code, d));
}

}  // namespace

BENCHMARK(Encode)
    ->ArgsProduct({{1, 3}, {512}, {1, 2}})
    ->Args({3, 2048, 1})
    ->Args({3, 2048, 2})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(Decode512)
    ->ArgsProduct({{1, 3}, {1, 4}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

BENCHMARK_MAIN();
