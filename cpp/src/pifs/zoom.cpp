#include "ifsforge/pifs/zoom.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/planes.h"

namespace ifsforge {
namespace {

constexpr std::size_t kRowChunks = 64;  // row chunks: fixed, so the output never depends on threads
constexpr double kKeysA = -0.5;    // Keys' cubic convolution parameter (the usual "bicubic")

double keys(double x) {
  x = std::abs(x);
  if (x < 1) return ((kKeysA + 2) * x - (kKeysA + 3)) * x * x + 1;
  if (x < 2) return ((kKeysA * x - 5 * kKeysA) * x + 8 * kKeysA) * x - 4 * kKeysA;
  return 0;
}

/// The four taps of output phase p of a 2^log_factor magnification: output pixel i·f + p has its
/// centre at source position i + (p + ½)/f − ½; the taps start at source pixel i + first.
struct Phase {
  int first;
  std::array<float, 4> weight;
};

std::vector<Phase> phases(int factor) {
  std::vector<Phase> out(factor);
  for (int p = 0; p < factor; ++p) {
    const double t = (p + 0.5) / factor - 0.5;
    const int base = int(std::floor(t));
    out[p].first = base - 1;
    for (int k = 0; k < 4; ++k) out[p].weight[k] = float(keys(t - (base - 1 + k)));
  }
  return out;
}

}  // namespace

PifsRaster upscale_bicubic(const PifsRaster& r, int log_factor, int threads) {
  const int f = 1 << log_factor;
  const std::vector<Phase> ph = phases(f);
  PifsRaster mid{r.width * f, r.height, {}}, out{r.width * f, r.height * f, {}};
  resize_large(mid.values, std::size_t(mid.width) * mid.height);  // huge pages, faulted in on every core
  resize_large(out.values, std::size_t(out.width) * out.height);
  auto clamp = [](int i, int n) { return std::clamp(i, 0, n - 1); };
  threads = pass_threads(threads, double(out.width) * out.height);
  // Rows across, then columns down; every output pixel is the same sum whichever job computes it.
  parallel_jobs(kRowChunks, threads, [&](std::size_t job, int) {
    for (int y = int(r.height * job / kRowChunks); y < int(r.height * (job + 1) / kRowChunks); ++y) {
      const float* src = r.row(y);
      float* dst = mid.row(y);
      for (int i = 0; i < r.width; ++i)
        for (int p = 0; p < f; ++p) {
          float s = 0;
          for (int k = 0; k < 4; ++k) s += ph[p].weight[k] * src[clamp(i + ph[p].first + k, r.width)];
          dst[i * f + p] = s;
        }
    }
  });
  parallel_jobs(kRowChunks, threads, [&](std::size_t job, int) {
    for (int y = int(out.height * job / kRowChunks); y < int(out.height * (job + 1) / kRowChunks); ++y) {
      const Phase& q = ph[y % f];
      std::array<const float*, 4> rows;
      for (int k = 0; k < 4; ++k) rows[k] = mid.row(clamp(y / f + q.first + k, r.height));
      float* dst = out.row(y);
      for (int x = 0; x < out.width; ++x)
        dst[x] = q.weight[0] * rows[0][x] + q.weight[1] * rows[1][x] + q.weight[2] * rows[2][x] +
                 q.weight[3] * rows[3][x];
    }
  });
  return out;
}

PifsRaster zoom_filter(const PifsRaster& fractal, const PifsRaster& native, int log_factor, int threads) {
  const ZoomSettings z = log_factor == 1 ? kZoomAt2 : kZoomAt4;
  PifsRaster x = upscale_bicubic(native, log_factor, threads);
  for (std::size_t i = 0; i < x.values.size(); ++i)
    x.values[i] = (1 - z.fractal_share) * x.values[i] + z.fractal_share * fractal.values[i];
  // Back-projection: the magnified image should average back to what was decoded.
  if (z.back_projection > 0) {
    PifsRaster error = resample_area(x, native.width, native.height);
    for (std::size_t i = 0; i < error.values.size(); ++i) error.values[i] = native.values[i] - error.values[i];
    const PifsRaster correction = upscale_bicubic(error, log_factor, threads);
    for (std::size_t i = 0; i < x.values.size(); ++i) x.values[i] += z.back_projection * correction.values[i];
  }
  return x;
}

}  // namespace ifsforge
