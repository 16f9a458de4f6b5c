#include "ifsforge/pifs/decoder.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/deblock.h"
#include "ifsforge/pifs/planes.h"
#include "ifsforge/pifs/residual.h"
#include "ifsforge/pifs/zoom.h"
#include "decode_steps.h"

namespace ifsforge {
namespace {

constexpr std::size_t kLeafChunks = 64;  // leaf chunks: fixed, so the output never depends on threads

/// One application of the PIFS operator writing `dst` at scale 2^l, its leaves in kLeafChunks chunks.
void apply(const PifsCode& code, const PifsPlane& plane, int l, const PifsRaster& src, bool from_half,
           PifsRaster& dst, int threads) {
  const std::size_t count = plane.leaves.size();
  threads = pass_threads(threads, double(dst.width) * dst.height);
  parallel_jobs(kLeafChunks, threads, [&](std::size_t job, int) {
    apply_leaves(code, plane, l, src, from_half, dst, count * job / kLeafChunks, count * (job + 1) / kLeafChunks);
  });
}

}  // namespace

void apply_leaves(const PifsCode& code, const PifsPlane& plane, int l, const PifsRaster& src, bool from_half,
                  PifsRaster& dst, std::size_t begin, std::size_t end) {
  for (std::size_t k = begin; k < end; ++k) {
    const PifsLeaf& leaf = plane.leaves[k];
    const int n = scaled_length(1 << leaf.log_size, l);
    const int x0 = scaled_length(leaf.x, l), y0 = scaled_length(leaf.y, l);
    const float dc = float(leaf.dc * code.dc_step);
    if (leaf.s == 0) {
      for (int v = 0; v < n; ++v) std::fill_n(dst.row(y0 + v) + x0, n, dc);
      continue;
    }
    const float s = float(code.s_value(leaf.s));
    const int size = 1 << leaf.log_size;
    if (from_half) {
      const float* d = src.row(scaled_length(leaf.dy * size, l - 1)) + scaled_length(leaf.dx * size, l - 1);
      const long stride = src.width;
      double sum = 0;
      for (int v = 0; v < n; ++v)
        for (int u = 0; u < n; ++u) sum += d[long(v) * stride + u];
      const float mean = float(sum / (double(n) * n));
      long origin, du, dv;
      isometry_walk(leaf.isometry, n, stride, origin, du, dv);
      for (int v = 0; v < n; ++v) {
        const float* p = d + origin + v * dv;
        float* out = dst.row(y0 + v) + x0;
        for (int u = 0; u < n; ++u) out[u] = s * (p[u * du] - mean) + dc;
      }
    } else {
      // φ: the 2n×2n domain averaged 2×2 (read through the isometry on the averaged grid).
      const float* d = src.row(scaled_length(leaf.dy * size, l)) + scaled_length(leaf.dx * size, l);
      const long stride = src.width;
      double sum = 0;
      for (int v = 0; v < 2 * n; ++v)
        for (int u = 0; u < 2 * n; ++u) sum += d[long(v) * stride + u];
      const float mean = float(sum / (4.0 * n * n));
      for (int v = 0; v < n; ++v) {
        float* out = dst.row(y0 + v) + x0;
        for (int u = 0; u < n; ++u) {
          int a, b;
          isometry_map(leaf.isometry, n, u, v, a, b);
          const float* p = d + long(2 * b) * stride + 2 * a;
          const float avg = 0.25f * (p[0] + p[1] + p[stride] + p[stride + 1]);
          out[u] = s * (avg - mean) + dc;
        }
      }
    }
  }
}

PifsRaster decode_plane(const PifsCode& code, const PifsPlane& plane, int log_scale, PifsDecoder decoder,
                        int iterations, int threads) {
  const int pw = code.padded(plane.width), ph = code.padded(plane.height);
  if (iterations <= 0) iterations = kDefaultIterations;
  const int coarsest = -code.min_log;  // the smallest range cells are one pixel there
  const int top = std::max(log_scale, coarsest);
  PifsRaster x;
  if (decoder == PifsDecoder::Iterative) {
    x = plane_raster(scaled_length(pw, top), scaled_length(ph, top), 128.f);
    PifsRaster next = plane_raster(x.width, x.height, 128.f);
    for (int i = 0; i < iterations; ++i) {
      apply(code, plane, top, x, false, next, threads);
      std::swap(x, next);
    }
  } else {
    // Baharav: the fixed point of the coarsest level, then each doubling is one pass whose
    // domains are the previous level's pixels (φ commutes with the 2×2 mean, so it is exact).
    x = plane_raster(scaled_length(pw, coarsest), scaled_length(ph, coarsest), 128.f);
    PifsRaster next = plane_raster(x.width, x.height, 128.f);
    for (int i = 0; i < iterations; ++i) {
      apply(code, plane, coarsest, x, false, next, threads);
      std::swap(x, next);
    }
    for (int l = coarsest + 1; l <= top; ++l) {
      next = plane_raster(scaled_length(pw, l), scaled_length(ph, l), 0.f);
      apply(code, plane, l, x, true, next, threads);
      std::swap(x, next);
    }
  }
  for (int l = top; l > log_scale; --l) x = resample_area(x, x.width / 2, x.height / 2);
  return x;
}

Image pifs_decode(const PifsCode& code, const PifsDecodeOptions& options) {
  int width = options.width, height = options.height;
  if (width <= 0 || height <= 0) {
    if (!(options.scale > 0) || !std::isfinite(options.scale))
      throw InputError("PIFS decode: scale must be a positive number");
    const double w = std::max(1.0, std::round(code.width * options.scale));
    const double h = std::max(1.0, std::round(code.height * options.scale));
    if (w > kMaxImageSide || h > kMaxImageSide)
      throw InputError("PIFS decode: scale " + std::to_string(options.scale) + " makes a " + std::to_string(w) + "x" +
                       std::to_string(h) + " image; at most " + std::to_string(kMaxImageSide) + " pixels per side");
    width = int(w);
    height = int(h);
  }
  if (width > kMaxImageSide || height > kMaxImageSide)
    throw InputError("PIFS decode: at most " + std::to_string(kMaxImageSide) + " pixels per side, got " +
                     std::to_string(width) + "x" + std::to_string(height));
  // The smallest power-of-two scale covering the request; other sizes are resampled from it.
  int m = -code.min_log;
  while ((double(code.width) * std::ldexp(1.0, m) < width || double(code.height) * std::ldexp(1.0, m) < height))
    ++m;
  const int full_w = int(std::ceil(code.width * std::ldexp(1.0, m)));
  const int full_h = int(std::ceil(code.height * std::ldexp(1.0, m)));
  // Each plane is decoded at the power-of-two size (its raster and the iteration's second
  // buffer, and three more while the zoom filter runs), then resampled; the image holds every
  // channel of the output.
  check_memory(double(full_w) * full_h * 4.0 * (5 * code.planes.size() + 1) + double(width) * height * code.channels * 8.0,
               "decoding a " + std::to_string(width) + "x" + std::to_string(height) + " image");
  // Planes decode independently: in parallel once their samples pay for a second thread (the
  // rule of every pass inside), each plane then on its share of the threads; a small image
  // decodes on one thread whatever is asked, so more threads never make it slower.
  std::vector<PifsRaster> planes(code.planes.size());
  const int threads = resolve_threads(options.threads);
  const int plane_threads =
      std::min(int(planes.size()), pass_threads(threads, double(full_w) * full_h * double(planes.size())));
  const int inner = std::max(1, threads / plane_threads);
  parallel_jobs(planes.size(), plane_threads, [&](std::size_t k, int) {
    const PifsPlane& plane = code.planes[k];
    // Chroma stored at half size is decoded one level finer (the seed's Step 6).
    const bool half = code.halved(k);
    const int lm = half ? m + 1 : m;
    PifsRaster p = decode_plane(code, plane, lm, options.decoder, options.iterations, inner);
    if (options.deblock) deblock(code, plane, lm, p, inner);
    add_residual(plane.residual, plane.width, plane.height, lm, p, inner);  // after deblocking, as encoded
    // A magnified output: the plane's own-size decode anchors the zoom filter (native-size
    // output, chroma included, is left as decoded).
    if (options.zoom == PifsZoom::Hybrid && m > 0 && lm > 0) {
      PifsRaster native = decode_plane(code, plane, 0, options.decoder, options.iterations, inner);
      if (options.deblock) deblock(code, plane, 0, native, inner);
      add_residual(plane.residual, plane.width, plane.height, 0, native, inner);
      p = zoom_filter(p, native, lm, inner);
    }
    // Crop away the padding (in place: rows only move toward the front).
    const int cw = std::min(full_w, p.width), ch = std::min(full_h, p.height);
    for (int y = 1; y < ch && cw < p.width; ++y)
      std::copy_n(p.values.data() + std::size_t(y) * p.width, cw, p.values.data() + std::size_t(y) * cw);
    p.width = cw;
    p.height = ch;
    p.values.resize(std::size_t(cw) * ch);
    planes[k] = cw == width && ch == height ? std::move(p) : resample_area(p, width, height);
  });
  return planes_to_image(planes, code.channels, code.color, width, height, threads);
}

}  // namespace ifsforge
