// The speed targets of fractal compression, both cores: encoding 512² gray < 1 s,
// 512² colour < 2 s; decoding 512² < 10 ms; 4× super-resolution of 512² (2048² out) < 100 ms.
// The image is a PNG named by IFSFORGE_PIFS_IMAGE (e.g. skimage's camera saved as PNG), else a
// synthetic photograph-like texture (several octaves of sines plus hashed noise).
// Run: build/cpp/bench/bench_pifs [--benchmark_filter=...]
#include <benchmark/benchmark.h>

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
    if (png.channels == channels) return png;
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

PifsEncodeOptions options() {
  PifsEncodeOptions o;
  o.ratio = 50;
  o.threads = 2;
  return o;
}

void EncodeGray512(benchmark::State& state) {
  const Image im = test_image(1);
  for (auto _ : state) benchmark::DoNotOptimize(pifs_encode(im, options()));
}
void EncodeColor512(benchmark::State& state) {
  const Image im = test_image(3);
  for (auto _ : state) benchmark::DoNotOptimize(pifs_encode(im, options()));
}
void Decode512(benchmark::State& state) {
  const PifsCode code = pifs_encode(test_image(int(state.range(0))), options());
  PifsDecodeOptions d;
  d.scale = double(state.range(1));
  d.threads = 2;
  for (auto _ : state) benchmark::DoNotOptimize(pifs_decode(code, d));
}

}  // namespace

BENCHMARK(EncodeGray512)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(EncodeColor512)->Unit(benchmark::kMillisecond)->UseRealTime();
// (channels, scale): 512² gray and colour at 1×, and their 4× super-resolution.
BENCHMARK(Decode512)->Args({1, 1})->Args({3, 1})->Args({1, 4})->Args({3, 4})->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
