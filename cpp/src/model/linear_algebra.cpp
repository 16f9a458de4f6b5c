#include "ifsforge/model/linear_algebra.h"

#include <algorithm>
#include <cmath>

namespace ifsforge::la {

Matrix block(const AffineMap& map, int k) {
  Matrix m{};
  k = std::min(k, kMaxDim);
  for (int r = 0; r < k; ++r)
    for (int c = 0; c < k; ++c) m[r][c] = map.a(r, c);
  return m;
}

bool invert(const Matrix& m, int n, Matrix& out) {
  Matrix a = m;
  Matrix inv{};
  double scale = 0.0;
  for (int r = 0; r < n; ++r) {
    inv[r][r] = 1.0;
    for (int c = 0; c < n; ++c) scale = std::max(scale, std::abs(a[r][c]));
  }
  if (scale == 0.0) return false;
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    // Relative threshold: a pivot this small means the matrix is singular to working precision.
    if (std::abs(a[pivot][col]) <= 1e-13 * scale) return false;
    std::swap(a[pivot], a[col]);
    std::swap(inv[pivot], inv[col]);
    const double p = a[col][col];
    for (int c = 0; c < n; ++c) {
      a[col][c] /= p;
      inv[col][c] /= p;
    }
    for (int r = 0; r < n; ++r) {
      if (r == col) continue;
      const double f = a[r][col];
      if (f == 0.0) continue;
      for (int c = 0; c < n; ++c) {
        a[r][c] -= f * a[col][c];
        inv[r][c] -= f * inv[col][c];
      }
    }
  }
  out = inv;
  return true;
}

double determinant(Matrix a, int n) {
  double det = 1.0;
  for (int col = 0; col < n; ++col) {
    int pivot = col;
    for (int r = col + 1; r < n; ++r)
      if (std::abs(a[r][col]) > std::abs(a[pivot][col])) pivot = r;
    if (a[pivot][col] == 0.0) return 0.0;
    if (pivot != col) {
      std::swap(a[pivot], a[col]);
      det = -det;
    }
    det *= a[col][col];
    for (int r = col + 1; r < n; ++r) {
      const double f = a[r][col] / a[col][col];
      for (int c = col; c < n; ++c) a[r][c] -= f * a[col][c];
    }
  }
  return det;
}

double spectral_norm(const Matrix& m, int n) {
  // S = M^T M is symmetric positive semi-definite; cyclic Jacobi converges quadratically.
  Matrix s{};
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double v = 0.0;
      for (int k = 0; k < n; ++k) v += m[k][i] * m[k][j];
      s[i][j] = v;
    }
  for (int sweep = 0; sweep < 60; ++sweep) {
    double off = 0.0;
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) off += s[i][j] * s[i][j];
    if (off < 1e-30) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        if (s[p][q] == 0.0) continue;
        const double theta = (s[q][q] - s[p][p]) / (2.0 * s[p][q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), sn = t * c;
        for (int k = 0; k < n; ++k) {
          const double skp = s[k][p], skq = s[k][q];
          s[k][p] = c * skp - sn * skq;
          s[k][q] = sn * skp + c * skq;
        }
        for (int k = 0; k < n; ++k) {
          const double spk = s[p][k], sqk = s[q][k];
          s[p][k] = c * spk - sn * sqk;
          s[q][k] = sn * spk + c * sqk;
        }
      }
  }
  double largest = 0.0;
  for (int i = 0; i < n; ++i) largest = std::max(largest, s[i][i]);
  return std::sqrt(largest);
}

void qr(const Matrix& m, int n, Matrix& q, Matrix& r) {
  // Householder reflections: Q stays orthogonal even when M is singular.
  r = m;
  q = Matrix{};
  for (int i = 0; i < n; ++i) q[i][i] = 1.0;
  for (int k = 0; k + 1 < n; ++k) {
    double norm = 0.0;
    for (int i = k; i < n; ++i) norm += r[i][k] * r[i][k];
    norm = std::sqrt(norm);
    if (norm < 1e-300) continue;
    std::array<double, kMaxDim> v{};
    const double alpha = r[k][k] > 0 ? -norm : norm;
    for (int i = k; i < n; ++i) v[i] = r[i][k];
    v[k] -= alpha;
    double vv = 0.0;
    for (int i = k; i < n; ++i) vv += v[i] * v[i];
    if (vv < 1e-300) continue;
    for (int c = 0; c < n; ++c) {  // R <- H R
      double dot = 0.0;
      for (int i = k; i < n; ++i) dot += v[i] * r[i][c];
      for (int i = k; i < n; ++i) r[i][c] -= 2.0 * dot / vv * v[i];
    }
    for (int row = 0; row < n; ++row) {  // Q <- Q H
      double dot = 0.0;
      for (int i = k; i < n; ++i) dot += q[row][i] * v[i];
      for (int i = k; i < n; ++i) q[row][i] -= 2.0 * dot / vv * v[i];
    }
  }
  // Make the diagonal of R non-negative (all but the last row, whose sign carries det Q).
  for (int k = 0; k < n; ++k) {
    if (r[k][k] >= 0.0) continue;
    for (int c = 0; c < n; ++c) r[k][c] = -r[k][c];
    for (int row = 0; row < n; ++row) q[row][k] = -q[row][k];
  }
  // Q must be a rotation: push a reflection into the last row of R.
  if (determinant(q, n) < 0.0) {
    for (int c = 0; c < n; ++c) r[n - 1][c] = -r[n - 1][c];
    for (int row = 0; row < n; ++row) q[row][n - 1] = -q[row][n - 1];
  }
}

}  // namespace ifsforge::la
