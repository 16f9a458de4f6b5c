// PIFS domain search: the exhaustive search finds the least-squares optimum of Eq. 29 (checked
// against a brute force written here in double), the tree search never beats it and equals it
// when searching everything, and the rate control's file is the same for any thread count in
// both modes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "ifsforge/io/pifs_file.h"
#include "ifsforge/pifs/code_bytes.h"
#include "ifsforge/pifs/domain_search.h"
#include "ifsforge/pifs/encoder.h"
#include "ifsforge/pifs/plane_coding.h"

using namespace ifsforge;

namespace {

PifsRaster noisy_plane(int side, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> noise(-20.f, 20.f);
  PifsRaster r;
  r.width = r.height = side;
  r.values.resize(std::size_t(side) * side);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      r.row(y)[x] = std::round(std::clamp(128.f + 60.f * std::sin(x * 0.3f) * std::cos(y * 0.2f) + noise(rng), 0.f, 255.f));
  return r;
}

/// The smallest collage error of range (x0, y0) over every domain and isometry with s quantised
/// as the encoder does (|s_q| ≥ 1), in double: Σ (s·(φ(d) − mean_φ) + dc − r)².
double brute_force(const PifsCode& code, const PifsRaster& plane, const PifsRaster& half, int n, int x0, int y0,
                   double dc) {
  const double s_scale = double(1 << (code.s_bits - 1));
  const int nx = plane.width / n - 1, ny = plane.height / n - 1;  // domain_count
  double mean_r = 0;
  for (int v = 0; v < n; ++v)
    for (int u = 0; u < n; ++u) mean_r += plane.row(y0 + v)[x0 + u];
  mean_r /= n * n;
  double best = INFINITY;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const float* d = half.row(j * n / 2) + i * n / 2;
      double mean_d = 0;
      for (int v = 0; v < n; ++v)
        for (int u = 0; u < n; ++u) mean_d += d[long(v) * half.width + u];
      mean_d /= n * n;
      for (int iso = 0; iso < 8; ++iso) {
        double dot = 0, de = 0;
        for (int v = 0; v < n; ++v)
          for (int u = 0; u < n; ++u) {
            int a, b;
            isometry_map(iso, n, u, v, a, b);
            const double p = d[long(b) * half.width + a] - mean_d;
            dot += (plane.row(y0 + v)[x0 + u] - mean_r) * p;
            de += p * p;
          }
        if (de <= 0) continue;
        const int q = std::clamp(int(std::lround(dot / de * s_scale)), -code.s_limit(), code.s_limit());
        if (q == 0) continue;
        const double s = q / s_scale;
        double err = 0;
        for (int v = 0; v < n; ++v)
          for (int u = 0; u < n; ++u) {
            int a, b;
            isometry_map(iso, n, u, v, a, b);
            err += std::pow(s * (d[long(b) * half.width + a] - mean_d) + dc - plane.row(y0 + v)[x0 + u], 2);
          }
        best = std::min(best, err);
      }
    }
  return best;
}

/// Every range block of the 32×32 `plane` at sizes 4 and 8 searched by `tree` and by the
/// exhaustive search: check(half plane, n, col, row, tree's candidate, exhaustive's candidate).
template <class Check>
void compare_searches(const PifsCode& code, const PifsRaster& plane, const PifsSearch& tree, Check check) {
  const PifsRaster half = half_plane(plane);
  PifsSearch all;
  all.mode = PifsDomainSearch::Exhaustive;
  for (int log = 2; log <= 3; ++log) {
    const int n = 1 << log, blocks = 32 / n;
    const PifsDomains pool = domain_pool(half, 32, 32, log);
    for (int row = 0; row < blocks; ++row) {
      std::vector<PifsCandidate> fast(blocks), best(blocks);
      search_row(code, plane, half, pool, tree, row, fast.data());
      search_row(code, plane, half, pool, all, row, best.data());
      for (int col = 0; col < blocks; ++col) check(half, n, col, row, fast[col], best[col]);
    }
  }
}

PifsCode two_level_code() {
  PifsCode code;
  code.min_log = 2;
  code.max_log = 3;
  return code;
}

}  // namespace

TEST(PifsSearch, ExhaustiveFindsTheLeastSquaresOptimumAndTheTreeNeverBeatsIt) {
  const PifsCode code = two_level_code();
  const PifsRaster plane = noisy_plane(32, 7);
  int checked = 0;
  compare_searches(code, plane, PifsSearch(), [&](const PifsRaster& half, int n, int col, int row,
                                                  const PifsCandidate& fast, const PifsCandidate& b) {
    const double exact = brute_force(code, plane, half, n, col * n, row * n, b.flat.dc * code.dc_step);
    ASSERT_TRUE(b.has_transform) << "noise gives every block a transform";
    EXPECT_NEAR(b.transform_error, exact, 1e-3 * exact + 1e-6) << "block " << col << "," << row;
    EXPECT_GE(fast.has_transform ? fast.transform_error : INFINITY, b.transform_error * (1 - 1e-4));
    ++checked;
  });
  EXPECT_EQ(checked, 8 * 8 + 4 * 4);
}

TEST(PifsSearch, TreeWithEveryViewAndEveryLeafFindsTheExhaustiveOptimum) {
  // All 16 views of each range (margin 2 admits every one), every leaf and a result list longer
  // than the pool: each (domain, isometry) pair reaches the exact fit once, through the view
  // index its result carries, so the tree's best equals the exhaustive search's.
  PifsSearch tree;
  tree.orientation_margin = 2;
  tree.max_leaves = 1 << 20;
  tree.neighbours = tree.pooled_neighbours = 1 << 16;
  tree.full_effort_rms = 0;
  compare_searches(two_level_code(), noisy_plane(32, 11), tree,
                   [](const PifsRaster&, int n, int col, int row, const PifsCandidate& fast, const PifsCandidate& best) {
                     ASSERT_TRUE(fast.has_transform && best.has_transform);
                     EXPECT_NEAR(fast.transform_error, best.transform_error, 1e-4 * best.transform_error)
                         << "size " << n << " block " << col << "," << row;
                   });
}

TEST(PifsSearch, SameBytesForAnyThreadCountInBothModes) {
  Image im(72, 56, 1);
  const PifsRaster p = noisy_plane(72, 3);
  for (int y = 0; y < 56; ++y)
    for (int x = 0; x < 72; ++x) im.at(x, y, 0) = p.row(y)[x] / 255.f;
  for (PifsDomainSearch mode : {PifsDomainSearch::Tree, PifsDomainSearch::Exhaustive}) {
    PifsEncodeOptions o;
    o.ratio = 6;
    o.search.mode = mode;
    o.threads = 1;
    const auto one = pifs_to_bytes(pifs_encode(im, o));
    for (int threads : {2, 3}) {
      o.threads = threads;
      EXPECT_EQ(one, pifs_to_bytes(pifs_encode(im, o))) << threads << " threads, " << name_of(mode);
    }
  }
}
