#include "ifsforge/render/image_based.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/pages.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/pixel_space.h"

namespace ifsforge {

namespace {
// A covered texel's bilinear sample: 1 at its centre, falling to 0 a texel away. Against PRR
// over the planar samples, a lower bar also keeps neighbours of the spiral's thin arms and a
// higher one loses the tree's twigs; this one keeps both (tests/python/test_fidelity.py).
constexpr float kCoveredSample = 0.82f;
constexpr int kMaxSubsamples = 8;
}  // namespace

int image_based_iterations(const Ifs& ifs, int width, int height) {
  double s = 0.0;
  for (double f : ifs.spatial_contraction_factors()) s = std::max(s, f);
  if (!(s < 1.0))
    throw InputError("image-based rendering needs every map to shrink the image: system '" + ifs.name() +
                     "' has a map with contraction factor " + std::to_string(s));
  if (s == 0.0) return 1;
  return std::max(1, static_cast<int>(std::ceil(std::log(static_cast<double>(std::max(width, height))) / -std::log(s))) + 1);
}

namespace {

/// Bilinear sample of a (w x h x stride) float image at continuous pixel coordinates; pixel
/// centres sit at half-integers and the image is zero outside.
inline void bilinear(const float* image, int w, int h, int stride, double x, double y, float* out) {
  x -= 0.5;
  y -= 0.5;
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
  const float fx = static_cast<float>(x - fx0), fy = static_cast<float>(y - fy0);
  const float weights[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  for (int k = 0; k < stride; ++k) out[k] = 0.0f;
  for (int corner = 0; corner < 4; ++corner) {
    const int xi = x0 + (corner & 1), yi = y0 + (corner >> 1);
    if (xi < 0 || yi < 0 || xi >= w || yi >= h) continue;
    const float* texel = image + (std::size_t(yi) * w + xi) * stride;
    for (int k = 0; k < stride; ++k) out[k] += weights[corner] * texel[k];
  }
}

/// The same for one channel, returned (the binary images' hot loop).
inline float bilinear1(const float* image, int w, int h, double x, double y) {
  x -= 0.5;
  y -= 0.5;
  const double fx0 = std::floor(x), fy0 = std::floor(y);
  const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
  const float fx = static_cast<float>(x - fx0), fy = static_cast<float>(y - fy0);
  if (x0 >= 0 && y0 >= 0 && x0 + 1 < w && y0 + 1 < h) {  // inside: no edge tests
    const float* t = image + std::size_t(y0) * w + x0;
    const float top = t[0] + fx * (t[1] - t[0]), bottom = t[w] + fx * (t[w + 1] - t[w]);
    return top + fy * (bottom - top);
  }
  float out;
  bilinear(image, w, h, 1, x + 0.5, y + 0.5, &out);
  return out;
}

}  // namespace

Capabilities ImageBased::capabilities() const {
  // Textures shrunk by every map.
  using C = Capabilities;
  return {C::Condensation | C::Overlapping | C::Plane};
}

Raster ImageBased::draw(const Ifs& ifs, const RenderOptions& options) const {
  const ParameterValues params(*this, options);
  const int supersample = static_cast<int>(params.integer("supersample", 1, 8));
  const PixelSpace space = make_pixel_space(ifs, options, name(), supersample);
  if (space.channels && space.spatial_reads_channels)
    throw InputError("image-based rendering maps textures: the spatial rows of system '" + ifs.name() +
                     "' must not read its color channels");
  const bool measure = params.choice("weights", {"attractor", "measure"}) == "measure";
  const int iterations = params.automatic("iterations") ? image_based_iterations(ifs, space.width, space.height)
                                                        : static_cast<int>(params.integer("iterations", 1, 100000));
  const double threshold = params.number("threshold", 0.0, 1.0);
  const int w = space.width, h = space.height, ch = space.channels, stride = 1 + ch;
  const std::size_t pixels = space.pixels();
  check_memory(2.0 * pixels * stride * 4.0, "two " + std::to_string(w) + "x" + std::to_string(h) + " IBR textures");
  const std::size_t n = space.maps.size();
  const double share = ifs.condensation().empty() ? 0.0 : ifs.condensation().probability;
  std::vector<double> weight(n);
  std::vector<bool> singular(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double det = std::abs(space.maps[i].determinant());
    const PixelMap& m = space.maps[i];
    const double scale = std::max({std::abs(m.a), std::abs(m.b), std::abs(m.c), std::abs(m.d)});
    singular[i] = !(det > 1e-12 * scale * scale);
    const double p = ifs.probabilities()[i] * (1.0 - share);
    weight[i] = !measure ? 1.0 : singular[i] ? p : p / det;  // Eq. 64 (pixel areas: det is the same)
  }
  const std::vector<std::uint32_t> condensation = condensation_pixels(ifs, space.frame);
  // Attractor weights sample each pixel's pre-image on a k x k grid and keep the largest
  // value: one bilinear sample at the pre-image of the centre skips source pixels (the
  // pre-images of neighbouring pixels lie 1/s pixels apart), so pieces thinner than that
  // vanish (most of the Cantor dust's pixels, for one). k = ceil(1/s) for the map's largest
  // stretch of the inverse, at most 4, brings the samples within a source pixel of each other.
  std::vector<int> subsamples(n, 1);
  for (std::size_t i = 0; i < n && !measure; ++i) {
    if (singular[i]) continue;
    const PixelMap& m = space.maps[i];
    const double det = m.determinant();
    const double stretch = std::max(std::hypot(m.d, m.c), std::hypot(m.b, m.a)) / std::abs(det);
    subsamples[i] = static_cast<int>(std::clamp(std::ceil(2.0 * stretch - 1e-9), 1.0, double(kMaxSubsamples)));
  }

  // Texel layout: q, then q * channel values (premultiplied, so that bilinear filtering and
  // sums of copies average the colours by coverage).
  const Point start = ifs.start_point();
  // On huge pages: a 2000^2 texture pair faulted in 4 KB at a time cost a sixth of a render.
  // The buffers of a 16000^2 grid (8000^2 supersampled) take seconds to fault in: Ctrl-C hears it.
  const ProgressCallback poll_start = progress_range(options.progress, 0.0, 0.0);
  std::vector<float> q, next;
  assign_large(q, pixels * stride, 0.0f, poll_start);
  assign_large(next, pixels * stride, 0.0f, poll_start);
  constexpr int kRowsPerJob = 16;
  const std::size_t jobs = (h + kRowsPerJob - 1) / kRowsPerJob;
  // The white image, on every core and within reach of Ctrl-C (16000^2 texels at 8000^2).
  parallel_jobs(jobs, options.threads, [&](std::size_t job, int) {
    const std::size_t end = std::min(pixels, (job + 1) * kRowsPerJob * std::size_t(w));
    for (std::size_t p = job * kRowsPerJob * std::size_t(w); p < end; ++p) {
      q[p * stride] = 1.0f;
      for (int c = 0; c < ch; ++c) q[p * stride + 1 + c] = static_cast<float>(start[2 + c]);
    }
  }, poll_start);
  std::vector<std::uint64_t> samples(jobs, 0);
  std::uint64_t operations = 0;
  // Coverage (attractor weights, no channels): a summed-area table of the covered texels lets
  // a pre-image footprint with nothing covered skip its samples (most of the image).
  const bool coverage = !ch && !measure;
  std::vector<std::uint32_t> area;
  assign_large(area, coverage ? std::size_t(w + 1) * (h + 1) : 0, 0u, poll_start);
  auto covered_in = [&](int x0, int y0, int x1, int y1) {  // texels [x0, x1) x [y0, y1)
    x0 = std::clamp(x0, 0, w), x1 = std::clamp(x1, 0, w), y0 = std::clamp(y0, 0, h), y1 = std::clamp(y1, 0, h);
    if (x1 <= x0 || y1 <= y0) return false;
    const std::size_t s = w + 1;
    return area[y1 * s + x1] - area[y0 * s + x1] - area[y1 * s + x0] + area[y0 * s + x0] > 0;
  };
  // Both cores build the table: counts along each row, then down each stripe of columns.
  constexpr int kColumnsPerJob = 256;
  auto build_area = [&](const ProgressCallback& poll) {
    const std::size_t s = w + 1;
    parallel_jobs(jobs, options.threads, [&](std::size_t job, int) {
      const int y_end = std::min(h, static_cast<int>(job + 1) * kRowsPerJob);
      for (int y = static_cast<int>(job) * kRowsPerJob; y < y_end; ++y) {
        std::uint32_t* out = &area[(y + 1) * s + 1];
        const float* in = &q[std::size_t(y) * w];
        std::uint32_t sum = 0;
        for (int x = 0; x < w; ++x) out[x] = sum += in[x] > 0.0f;
      }
    }, poll);
    parallel_jobs((w + kColumnsPerJob - 1) / kColumnsPerJob, options.threads, [&](std::size_t job, int) {
      const std::size_t x0 = 1 + job * kColumnsPerJob, x1 = std::min<std::size_t>(s, x0 + kColumnsPerJob);
      for (int y = 1; y < h; ++y)
        for (std::size_t x = x0; x < x1; ++x) area[(y + 1) * s + x] += area[y * s + x];
    }, poll);
  };
  for (int iteration = 0; iteration < iterations; ++iteration) {
    const double done = static_cast<double>(iteration) / iterations;
    // The passes around the sampling hear Ctrl-C too (progress stays at the iteration's start).
    const ProgressCallback poll = progress_range(options.progress, done, done);
    if (coverage) build_area(poll);
    parallel_jobs(jobs, options.threads, [&](std::size_t job, int) {
      std::uint64_t count = 0;
      float texel[1 + kMaxDim];
      const int y_end = std::min(h, static_cast<int>(job + 1) * kRowsPerJob);
      for (int y = static_cast<int>(job) * kRowsPerJob; y < y_end; ++y) {
        float* row = &next[std::size_t(y) * w * stride];
        std::fill(row, row + std::size_t(w) * stride, 0.0f);
        for (std::size_t i = 0; i < n; ++i) {
          if (singular[i]) continue;
          const PixelMap& m = space.maps[i];
          const double det = m.determinant();
          const double ia = m.d / det, ib = -m.b / det, ic = -m.c / det, id = m.a / det;
          // Pre-image of pixel centre (x + 0.5, y + 0.5): base + x * step.
          const double rx = 0.5 - m.e, ry = y + 0.5 - m.f;
          const double bx = ia * rx + ib * ry, by = ic * rx + id * ry, sx = ia, sy = ic;
          // The x where the pre-image lies in the source image [0, w] x [0, h]: the quadrilateral w_i(image) on this row.
          double lo = 0.0, hi = w - 1.0;
          auto clip = [&](double base, double step, double limit) {
            if (step == 0.0) {
              if (base < 0.0 || base > limit) hi = -1.0;
              return;
            }
            double t0 = (0.0 - base) / step, t1 = (limit - base) / step;
            if (t0 > t1) std::swap(t0, t1);
            lo = std::max(lo, t0);
            hi = std::min(hi, t1);
          };
          clip(bx, sx, w);
          clip(by, sy, h);
          if (hi < lo) continue;
          const int x0 = static_cast<int>(std::ceil(lo)), x1 = static_cast<int>(std::floor(hi));
          const float sc = static_cast<float>(weight[i]);
          if (!ch && measure) {
            for (int x = x0; x <= x1; ++x) row[x] += sc * bilinear1(q.data(), w, h, bx + x * sx, by + x * sy);
            count += x1 - x0 + 1;
            continue;
          }
          if (coverage) {
            // Covered when some sample of the pre-image reads a covered texel: the largest of
            // k x k samples, any map (a union of binary pictures).
            const int k = subsamples[i];
            double du[kMaxSubsamples * kMaxSubsamples], dv[kMaxSubsamples * kMaxSubsamples];
            for (int a = 0; a < k; ++a)
              for (int b = 0; b < k; ++b) {
                const double u = (a + 0.5) / k - 0.5, v = (b + 0.5) / k - 0.5;  // offsets from the centre
                du[a * k + b] = ia * u + ib * v;
                dv[a * k + b] = ic * u + id * v;
              }
            // Half the footprint's box plus the bilinear reach of a sample.
            const double rx = 0.5 * (std::abs(ia) + std::abs(ib)) + 1.0, ry = 0.5 * (std::abs(ic) + std::abs(id)) + 1.0;
            for (int x = x0; x <= x1; ++x) {
              if (row[x] >= kCoveredSample) continue;
              const double px = bx + x * sx, py = by + x * sy;
              if (!covered_in(static_cast<int>(std::floor(px - 0.5 - rx)), static_cast<int>(std::floor(py - 0.5 - ry)),
                              static_cast<int>(std::ceil(px - 0.5 + rx)) + 1, static_cast<int>(std::ceil(py - 0.5 + ry)) + 1))
                continue;
              for (int j = 0; j < k * k && row[x] < kCoveredSample; ++j) {
                row[x] = std::max(row[x], bilinear1(q.data(), w, h, px + du[j], py + dv[j]));
                ++count;
              }
            }
            continue;
          }
          for (int x = x0; x <= x1; ++x) {
            const double px = bx + x * sx, py = by + x * sy;
            bilinear(q.data(), w, h, stride, px, py, texel);
            ++count;
            if (texel[0] <= 0.0f) continue;
            float* out = row + std::size_t(x) * stride;
            out[0] += sc * texel[0];
            if (!ch) continue;
            // The copy's colour: the map's channel rows on (pre-image, colour there).
            Point p{}, r{};
            p[0] = px;
            p[1] = py;
            for (int c = 0; c < ch; ++c) p[2 + c] = texel[1 + c] / texel[0];
            m.map.apply(p.data(), r.data());
            for (int c = 0; c < ch; ++c) out[1 + c] += sc * texel[0] * static_cast<float>(r[2 + c]);
          }
        }
      }
      samples[job] = count;
    }, progress_range(options.progress, done, done + 1.0 / iterations));
    for (std::uint64_t c : samples) operations += c;
    // Maps with no inverse: splat the picture forwards, in pixel order (deterministic). On a
    // large picture the first iterations splat every texel, a long loop: Ctrl-C hears it.
    for (std::size_t i = 0; i < n; ++i) {
      if (!singular[i]) continue;
      double values[kMaxDim];
      std::vector<float> color(ch);
      for (std::size_t p = 0; p < pixels; ++p) {
        poll_now_and_then(p, poll);
        const float v = q[p * stride];
        if (v <= 0.0f) continue;
        for (int c = 0; c < ch; ++c) color[c] = q[p * stride + 1 + c] / v;
        const long long target = space.map_pixel(i, static_cast<std::uint32_t>(p), color.data(), values);
        ++operations;
        if (target < 0) continue;
        float* out = &next[std::size_t(target) * stride];
        out[0] += static_cast<float>(weight[i]) * v;
        for (int c = 0; c < ch; ++c) out[1 + c] += static_cast<float>(weight[i] * v * values[c]);
      }
    }
    if (measure) {
      // The condensation set's share of the mass, evenly on its pixels (the maps carry 1 - p_0).
      double total = 0.0;
      for (std::size_t p = 0; p < pixels; ++p) total += q[p * stride];
      for (std::uint32_t p : condensation) {
        next[p * stride] += static_cast<float>(share * total / condensation.size());
        for (int c = 0; c < ch; ++c)
          next[p * stride + 1 + c] += static_cast<float>(share * total / condensation.size() * ifs.condensation().channels[c]);
      }
    } else {
      parallel_jobs(jobs, options.threads, [&](std::size_t job, int) {
        const std::size_t end = std::min(pixels, (job + 1) * kRowsPerJob * std::size_t(w));
        for (std::size_t p = job * kRowsPerJob * std::size_t(w); p < end; ++p) {
          float* t = &next[p * stride];
          if (t[0] > 1.0f) {
            for (int c = 0; c < ch; ++c) t[1 + c] /= t[0];
            t[0] = 1.0f;
          }
          // A binary picture stays binary: the largest sample of a covered pre-image is at
          // least about a half, while the bilinear tails beside it would grow the set by a
          // pixel per iteration.
          if (!ch) t[0] = t[0] >= kCoveredSample ? 1.0f : 0.0f;
        }
      }, poll);
      for (std::uint32_t p : condensation) {  // W(B) = C u w_1(B) u ...
        next[p * stride] = 1.0f;
        for (int c = 0; c < ch; ++c) next[p * stride + 1 + c] = static_cast<float>(ifs.condensation().channels[c]);
      }
    }
    q.swap(next);
    report_progress(options, static_cast<double>(iteration + 1) / iterations);
  }
  Raster raster = empty_raster(ifs, space);
  float peak = 0.0f;
  for (std::size_t p = 0; p < pixels; ++p) peak = std::max(peak, q[p * stride]);
  for (std::size_t p = 0; p < pixels; ++p) {
    const float v = q[p * stride];
    const bool covered = measure ? v > 1e-7f * peak : v >= threshold && v > 0.0f;
    if (!covered) continue;
    raster.density[p] = std::max(v, std::numeric_limits<float>::denorm_min());
    for (int c = 0; c < ch; ++c) raster.channels[p * ch + c] = q[p * stride + 1 + c] / v;
  }
  raster.points = operations;
  return reduce_supersampled(std::move(raster), supersample, measure);
}

}  // namespace ifsforge
