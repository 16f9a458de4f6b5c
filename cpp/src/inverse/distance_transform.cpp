#include "ifsforge/inverse/distance_transform.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"

namespace ifsforge {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// The lower envelope of parabolas y = (q - p)^2 + f[p]: d[q] = min_p ((q - p)^2 + f[p]).
/// `v`, `z` are scratch of n and n + 1 entries.
void transform_1d(const double* f, double* d, int n, int stride, std::vector<int>& v, std::vector<double>& z) {
  int k = -1;
  for (int q = 0; q < n; ++q) {
    const double fq = f[q * stride];
    if (fq == kInf) continue;
    while (k >= 0) {
      const int p = v[k];
      const double s = ((fq + double(q) * q) - (f[p * stride] + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k;
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInf : ((fq + double(q) * q) - (f[v[k - 1] * stride] + double(v[k - 1]) * v[k - 1])) /
                                 (2.0 * (q - v[k - 1]));
    z[k + 1] = kInf;
  }
  if (k < 0) {
    for (int q = 0; q < n; ++q) d[q * stride] = kInf;
    return;
  }
  int j = 0;
  for (int q = 0; q < n; ++q) {
    while (z[j + 1] < q) ++j;
    const double dq = q - v[j];
    d[q * stride] = dq * dq + f[v[j] * stride];
  }
}

void check_same_size(const PixelSet& a, const PixelSet& b) {
  if (a.width != b.width || a.height != b.height)
    throw InputError("pixel sets of different sizes: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                     " and " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

}  // namespace

std::size_t PixelSet::count() const {
  return static_cast<std::size_t>(std::count_if(cells.begin(), cells.end(), [](std::uint8_t c) { return c != 0; }));
}

std::vector<double> squared_distance_transform(const PixelSet& set) {
  const int w = set.width, h = set.height;
  std::vector<double> f(std::size_t(w) * h), d(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = set.cells[i] ? 0.0 : kInf;
  const int n = std::max(w, h);
  std::vector<int> v(n);
  std::vector<double> z(n + 1);
  // Columns, then rows: the squared distance separates (seed Eq. 12 on the grid, exact).
  for (int x = 0; x < w; ++x) transform_1d(f.data() + x, d.data() + x, h, w, v, z);
  for (int y = 0; y < h; ++y) transform_1d(d.data() + std::size_t(y) * w, f.data() + std::size_t(y) * w, w, 1, v, z);
  return f;
}

std::size_t VoxelSet::count() const {
  return static_cast<std::size_t>(std::count_if(cells.begin(), cells.end(), [](std::uint8_t c) { return c != 0; }));
}

std::vector<double> squared_distance_transform(const VoxelSet& set) {
  const int nx = set.grid.dims[0], ny = set.grid.dims[1], nz = set.grid.dims[2];
  std::vector<double> f(set.cells.size()), d(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = set.cells[i] ? 0.0 : kInf;
  const int n = std::max({nx, ny, nz});
  std::vector<int> v(n);
  std::vector<double> z(n + 1);
  // Along z, then y, then x: the squared distance separates in 3D as in 2D.
  const std::size_t slab = std::size_t(nx) * ny;
  for (std::size_t c = 0; c < slab; ++c) transform_1d(f.data() + c, d.data() + c, nz, static_cast<int>(slab), v, z);
  for (int k = 0; k < nz; ++k)
    for (int i = 0; i < nx; ++i)
      transform_1d(d.data() + k * slab + i, f.data() + k * slab + i, ny, nx, v, z);
  for (std::size_t row = 0; row < slab / nx * nz; ++row)
    transform_1d(f.data() + row * nx, d.data() + row * nx, nx, 1, v, z);
  return d;
}

double directed_hausdorff(const PixelSet& from, const PixelSet& to) {
  check_same_size(from, to);
  const auto dt = squared_distance_transform(to);
  double worst = 0;
  for (std::size_t i = 0; i < dt.size(); ++i)
    if (from.cells[i]) worst = std::max(worst, dt[i]);
  return std::sqrt(worst);
}

double hausdorff_distance(const PixelSet& a, const PixelSet& b) {
  return std::max(directed_hausdorff(a, b), directed_hausdorff(b, a));
}

}  // namespace ifsforge
