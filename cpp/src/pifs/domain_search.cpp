#include "ifsforge/pifs/domain_search.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/pifs/plane_coding.h"

namespace ifsforge {
namespace {

int quantise_mean(const PifsCode& code, double mean) {
  const int q = int(std::lround(mean / code.dc_step));
  return std::clamp(q, 0, 255 / code.dc_step);
}

}  // namespace

void half_rows(const PifsRaster& p, PifsRaster& h, int begin, int end) {
  for (int y = begin; y < end; ++y) {
    const float* a = p.row(2 * y);
    const float* b = p.row(2 * y + 1);
    float* out = h.row(y);
    for (int x = 0; x < h.width; ++x) out[x] = 0.25f * (a[2 * x] + a[2 * x + 1] + b[2 * x] + b[2 * x + 1]);
  }
}

PifsRaster half_plane(const PifsRaster& p, int threads, const ProgressCallback& progress) {
  PifsRaster h;
  h.width = p.width / 2;
  h.height = p.height / 2;
  h.values.resize(std::size_t(h.width) * h.height);
  parallel_jobs(std::size_t(h.height), threads, [&](std::size_t row, int) { half_rows(p, h, int(row), int(row) + 1); },
                progress);
  return h;
}

PifsDomains domain_pool(const PifsRaster& half, int padded_width, int padded_height, int log_size, bool with_tree) {
  PifsDomains pool;
  const int n = 1 << log_size;
  pool.log_size = log_size;
  pool.nx = std::max(0, domain_count(padded_width, log_size));
  pool.ny = std::max(0, domain_count(padded_height, log_size));
  pool.energy.resize(std::size_t(pool.nx) * pool.ny);
  const long stride = half.width;
  std::vector<BlockFeature> points;
  std::vector<std::uint32_t> tags;
  std::vector<float> norms;
  for (int j = 0; j < pool.ny; ++j) {
    if (stop_requested()) throw Cancelled();
    for (int i = 0; i < pool.nx; ++i) {
      const float* d = half.row(j * n / 2) + i * n / 2;
      double sum = 0, sq = 0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const double v = d[long(y) * stride + x];
          sum += v;
          sq += v * v;
        }
      const std::size_t id = std::size_t(j) * pool.nx + i;
      pool.energy[id] = sq - sum * sum / (n * n);
      BlockFeature f;
      if (!with_tree || !block_feature(d, stride, n, f)) continue;
      const Orientation o = canonical_orientation(f);
      points.push_back(transform_feature(f, o.isometry, o.negate));
      norms.push_back(float(std::sqrt(std::max(0.0, pool.energy[id]))));
      tags.push_back(std::uint32_t(id) << 4 | std::uint32_t(o.isometry) << 1 | std::uint32_t(o.negate));
    }
  }
  pool.tree = FeatureTree(points, std::move(tags), std::move(norms));
  return pool;
}

namespace {

/// One range block being fitted: its statistics and the best fit so far.
struct RangeFit {
  const PifsCode& code;
  const PifsDomains& domains;
  PifsCandidate& c;
  double s_scale, energy, dc_err, best;

  /// Eq. 29 least squares for domain `id` under isometry `iso`, given ⟨r − mean_r, φ(d)⟩ = `dot`
  /// (= ⟨r − mean_r, φ(d) − mean_d⟩), then s quantised to s_bits with |s| < 1.
  void consider(std::size_t id, int iso, double dot) {
    const double de = domains.energy[id];
    const int sq_q = std::clamp(int(std::lround(dot / de * s_scale)), -code.s_limit(), code.s_limit());
    if (sq_q == 0) return;
    const double s = sq_q / s_scale;
    const double err = energy - 2 * s * dot + s * s * de + dc_err;
    if (err < best) {
      best = err;
      c.has_transform = true;
      c.transform = c.flat;
      c.transform.s = std::int8_t(sq_q);
      c.transform.isometry = std::uint8_t(iso);
      c.transform.dx = std::uint16_t(id % domains.nx);
      c.transform.dy = std::uint16_t(id / domains.nx);
      c.transform_error = err;
    }
  }
};

/// The reference search: every domain under every isometry. `rt[(b·n + a)·8 + iso]` is the range
/// pixel (mean removed) that reads domain pixel (a, b) through `iso`, so the 8 dot products of a
/// domain accumulate side by side (in float: vector lanes; a reference may round at 1e-7).
void search_all(RangeFit& fit, const PifsRaster& half, const std::vector<float>& rt, int n) {
  const PifsDomains& domains = fit.domains;
  const long stride = half.width;
  for (std::size_t id = 0; id < domains.energy.size(); ++id) {
    if (domains.energy[id] <= 0) continue;
    const int i = int(id % domains.nx), j = int(id / domains.nx);
    const float* d = half.row(j * n / 2) + i * n / 2;
    float dot[8] = {};
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        const float v = d[long(b) * stride + a];
        const float* r = &rt[std::size_t(b * n + a) * 8];
        for (int iso = 0; iso < 8; ++iso) dot[iso] += r[iso] * v;
      }
    for (int iso = 0; iso < 8; ++iso) fit.consider(id, iso, dot[iso]);
  }
}

/// The tree search: the range's near-canonical views ask the tree together for the domains of
/// least estimated error, each then fitted exactly. A range whose RMS is below
/// search.full_effort_rms visits proportionally fewer leaves: its error, and so what a better
/// domain could save, is that much smaller.
void search_tree(RangeFit& fit, const PifsRaster& half, const PifsSearch& search, const std::vector<float>& r,
                 double mean, const BlockFeature& f, int n) {
  const PifsDomains& domains = fit.domains;
  const long stride = half.width;
  thread_local std::vector<std::uint64_t> found;
  Orientation views[16];
  BlockFeature queries[16];
  int undo[16];
  const int view_count = near_canonical_orientations(f, search.orientation_margin, views);
  for (int v = 0; v < view_count; ++v) {
    // The range seen canonically; a domain seen canonically near it matches the range through
    // the domain's orientation followed by the inverse of the range's.
    queries[v] = transform_feature(f, views[v].isometry, views[v].negate);
    undo[v] = inverse_isometry(views[v].isometry);
  }
  const double rms = std::sqrt(fit.energy / (double(n) * n));
  const double share = rms / search.full_effort_rms;  // ≥ 1 (or +inf): every leaf it may visit
  const int leaves = std::max(PifsSearch::kMinLeaves, share >= 1 ? search.max_leaves : int(search.max_leaves * share));
  const float s_max = float(fit.code.s_limit() / fit.s_scale);
  // Above 4×4 the feature pools the block, its estimate is looser: more results are fitted.
  const int k = n > 4 ? search.pooled_neighbours : search.neighbours;
  domains.tree.nearest(queries, view_count, float(std::sqrt(fit.energy)), s_max, k, leaves, found);
  for (std::uint64_t hit : found) {
    const std::uint32_t tag = std::uint32_t(hit >> 4);
    const std::size_t id = tag >> 4;
    if (domains.energy[id] <= 0) continue;
    const int iso = compose_isometry(int(tag >> 1) & 7, undo[hit & 15]);
    const int i = int(id % domains.nx), j = int(id / domains.nx);
    const float* d = half.row(j * n / 2) + i * n / 2;
    long origin, du, dv;
    isometry_walk(iso, n, stride, origin, du, dv);
    double dot = 0;
    for (int y = 0; y < n; ++y) {
      const float* p = d + origin + y * dv;
      const float* rr = &r[std::size_t(y) * n];
      for (int x = 0; x < n; ++x) dot += (rr[x] - mean) * p[x * du];
    }
    fit.consider(id, iso, dot);
  }
}

}  // namespace

void search_row(const PifsCode& code, const PifsRaster& plane, const PifsRaster& half, const PifsDomains& domains,
                const PifsSearch& search, int row, PifsCandidate* out) {
  const int log_size = domains.log_size;
  const int n = 1 << log_size;
  const int bx = plane.width >> log_size;
  const bool exhaustive = search.mode == PifsDomainSearch::Exhaustive;
  std::vector<float> r(std::size_t(n) * n), rt(exhaustive ? std::size_t(n) * n * 8 : 0);
  for (int col = 0; col < bx; ++col) {
    PifsCandidate& c = out[col];
    c = PifsCandidate();
    const int x0 = col * n, y0 = row * n;
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
    if (domains.energy.empty() || !block_feature(r.data(), n, n, f)) continue;
    RangeFit fit{code, domains, c, double(1 << (code.s_bits - 1)), energy, dc_err, c.flat_error};
    if (!exhaustive) {
      search_tree(fit, half, search, r, mean, f, n);
      continue;
    }
    for (int v = 0; v < n; ++v)
      for (int u = 0; u < n; ++u)
        for (int iso = 0; iso < 8; ++iso) {
          int a, b;
          isometry_map(iso, n, u, v, a, b);
          rt[std::size_t(b * n + a) * 8 + iso] = float(r[std::size_t(v) * n + u] - mean);
        }
    search_all(fit, half, rt, n);
  }
}

}  // namespace ifsforge
