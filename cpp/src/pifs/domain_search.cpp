#include "ifsforge/pifs/domain_search.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/block_search.h"
#include "ifsforge/pifs/plane_coding.h"

namespace ifsforge {
namespace {

/// φ of Eq. 29 for every domain at once: the plane averaged 2×2, so the 2r×2r domain at
/// (x, y) is the r×r block at (x/2, y/2).
PifsRaster half(const PifsRaster& p) {
  PifsRaster h;
  h.width = p.width / 2;
  h.height = p.height / 2;
  h.values.resize(std::size_t(h.width) * h.height);
  for (int y = 0; y < h.height; ++y) {
    const float* a = p.row(2 * y);
    const float* b = p.row(2 * y + 1);
    float* out = h.row(y);
    for (int x = 0; x < h.width; ++x) out[x] = 0.25f * (a[2 * x] + a[2 * x + 1] + b[2 * x] + b[2 * x + 1]);
  }
  return h;
}

int quantise_mean(const PifsCode& code, double mean) {
  const int q = int(std::lround(mean / code.dc_step));
  return std::clamp(q, 0, 255 / code.dc_step);
}

}  // namespace

std::vector<PifsCandidate> search_level(const PifsCode& code, const PifsRaster& plane, int log_size,
                                        const PifsSearch& search, int threads) {
  const int n = 1 << log_size;
  const int bx = plane.width >> log_size, by = plane.height >> log_size;
  const int nx = domain_count(plane.width, log_size), ny = domain_count(plane.height, log_size);
  const PifsRaster dom = half(plane);
  const long stride = dom.width;

  // Domain statistics and features: 8 isometries × 2 signs per non-flat domain.
  std::vector<double> dom_mean(std::size_t(std::max(nx, 0)) * std::max(ny, 0));
  std::vector<double> dom_energy(dom_mean.size());  // Σ (d − mean_d)²
  std::vector<BlockFeature> points;
  std::vector<std::uint32_t> tags;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float* d = dom.row(j * n / 2) + i * n / 2;
      double sum = 0, sq = 0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const double v = d[long(y) * stride + x];
          sum += v;
          sq += v * v;
        }
      const std::size_t id = std::size_t(j) * nx + i;
      dom_mean[id] = sum / (n * n);
      dom_energy[id] = sq - sum * sum / (n * n);
      BlockFeature f;
      if (!block_feature(d, stride, n, f)) continue;
      for (int iso = 0; iso < 8; ++iso)
        for (int neg = 0; neg < 2; ++neg) {
          points.push_back(transform_feature(f, iso, neg));
          tags.push_back(std::uint32_t(id) << 4 | std::uint32_t(iso) << 1 | std::uint32_t(neg));
        }
    }
  const FeatureTree tree(std::move(points), std::move(tags));

  std::vector<PifsCandidate> out(std::size_t(bx) * by);
  const double s_scale = double(1 << (code.s_bits - 1));
  parallel_jobs(std::size_t(by), threads, [&](std::size_t row, int) {
    std::vector<std::uint32_t> found;
    std::vector<float> r(std::size_t(n) * n);
    for (int col = 0; col < bx; ++col) {
      PifsCandidate& c = out[row * bx + col];
      const int x0 = col * n, y0 = int(row) * n;
      double sum = 0, sq = 0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const float v = plane.row(y0 + y)[x0 + x];
          r[y * n + x] = v;
          sum += v;
          sq += double(v) * v;
        }
      const double mean = sum / (n * n);
      const double energy = std::max(0.0, sq - sum * sum / (n * n));  // ‖r − mean_r‖²
      const int dc = quantise_mean(code, mean);
      const double dc_err = double(n) * n * std::pow(mean - dc * code.dc_step, 2);
      c.flat.x = std::uint16_t(x0);
      c.flat.y = std::uint16_t(y0);
      c.flat.log_size = std::uint8_t(log_size);
      c.flat.dc = std::uint8_t(dc);
      c.flat_error = energy + dc_err;
      BlockFeature f;
      if (tree.empty() || !block_feature(r.data(), n, n, f)) continue;
      tree.nearest(f, search.neighbours, search.max_leaves, found);
      double best = c.flat_error;
      for (std::uint32_t tag : found) {
        const std::size_t id = tag >> 4;
        const int iso = int(tag >> 1) & 7;
        const double de = dom_energy[id];
        if (de <= 0) continue;
        const int i = int(id % nx), j = int(id / nx);
        const float* d = dom.row(j * n / 2) + i * n / 2;
        long origin, du, dv;
        isometry_walk(iso, n, stride, origin, du, dv);
        // ⟨r − mean_r, d⟩ = ⟨r − mean_r, d − mean_d⟩.
        double dot = 0;
        for (int v = 0; v < n; ++v) {
          const float* p = d + origin + v * dv;
          const float* rr = &r[std::size_t(v) * n];
          for (int u = 0; u < n; ++u) dot += (rr[u] - mean) * p[u * du];
        }
        // Eq. 29 least squares, then s quantised to s_bits with |s| < 1.
        const int sq_q = std::clamp(int(std::lround(dot / de * s_scale)), -code.s_limit(), code.s_limit());
        if (sq_q == 0) continue;
        const double s = sq_q / s_scale;
        const double err = energy - 2 * s * dot + s * s * de + dc_err;
        if (err < best) {
          best = err;
          c.has_transform = true;
          c.transform = c.flat;
          c.transform.s = std::int8_t(sq_q);
          c.transform.isometry = std::uint8_t(iso);
          c.transform.dx = std::uint16_t(i);
          c.transform.dy = std::uint16_t(j);
          c.transform_error = err;
        }
      }
    }
  });
  return out;
}

}  // namespace ifsforge
