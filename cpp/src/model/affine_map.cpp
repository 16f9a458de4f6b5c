#include "ifsforge/model/affine_map.h"

#include <algorithm>
#include <cmath>

#include "ifsforge/core/error.h"
#include "ifsforge/model/linear_algebra.h"

namespace ifsforge {

AffineMap::AffineMap(int dim) : dim_(dim) {
  if (dim < 1 || dim > kMaxDim)
    throw InputError("a map needs 1 to " + std::to_string(kMaxDim) + " dimensions, got " +
                     std::to_string(dim));
  for (int i = 0; i < dim; ++i) a(i, i) = 1.0;
}

AffineMap::AffineMap(int dim, const std::vector<double>& matrix, const std::vector<double>& offset)
    : AffineMap(dim) {
  if (matrix.size() != static_cast<std::size_t>(dim * dim))
    throw InputError("a " + std::to_string(dim) + "D map needs a " + std::to_string(dim) + "x" +
                     std::to_string(dim) + " matrix, got " + std::to_string(matrix.size()) +
                     " numbers");
  if (offset.size() != static_cast<std::size_t>(dim))
    throw InputError("a " + std::to_string(dim) + "D map needs an offset of " +
                     std::to_string(dim) + " numbers, got " + std::to_string(offset.size()));
  for (int r = 0; r < dim; ++r) {
    for (int c = 0; c < dim; ++c) a(r, c) = matrix[r * dim + c];
    b(r) = offset[r];
  }
}

std::vector<double> AffineMap::matrix() const {
  std::vector<double> m(dim_ * dim_);
  for (int r = 0; r < dim_; ++r)
    for (int c = 0; c < dim_; ++c) m[r * dim_ + c] = a(r, c);
  return m;
}

std::vector<double> AffineMap::offset() const { return {b_.begin(), b_.begin() + dim_}; }

AffineMap AffineMap::compose(const AffineMap& inner) const {
  AffineMap out(dim_);
  compose_into(inner, out);
  return out;
}

namespace {

/// out = outer o inner in dimension D (0: the maps' own), unrolled when D is known.
template <int D>
void compose_in(const AffineMap& outer, const AffineMap& inner, AffineMap& out) {
  const int n = D ? D : outer.dim();
  for (int r = 0; r < n; ++r) {
    double offset = outer.b(r);
    for (int c = 0; c < n; ++c) {
      double v = 0.0;
      for (int k = 0; k < n; ++k) v += outer.a(r, k) * inner.a(k, c);
      out.a(r, c) = v;
      offset += outer.a(r, c) * inner.b(c);
    }
    out.b(r) = offset;
  }
}

}  // namespace

void AffineMap::compose_into(const AffineMap& inner, AffineMap& out) const {
  if (inner.dim_ != dim_) throw InputError("cannot compose maps of different dimensions");
  if (out.dim_ != dim_) out = AffineMap(dim_);
  // A recursion composes at every node: the common dimensions unrolled.
  if (dim_ == 2) return compose_in<2>(*this, inner, out);
  if (dim_ == 3) return compose_in<3>(*this, inner, out);
  compose_in<0>(*this, inner, out);
}

std::optional<AffineMap> AffineMap::inverse() const {
  la::Matrix m = la::block(*this, dim_);
  la::Matrix inv;
  if (!la::invert(m, dim_, inv)) return std::nullopt;
  AffineMap out(dim_);
  for (int r = 0; r < dim_; ++r) {
    double offset = 0.0;
    for (int c = 0; c < dim_; ++c) {
      out.a(r, c) = inv[r][c];
      offset -= inv[r][c] * b(c);
    }
    out.b(r) = offset;
  }
  return out;
}

double AffineMap::determinant(int k) const {
  if (k <= 0 || k > dim_) k = dim_;
  return la::determinant(la::block(*this, k), k);
}

double AffineMap::contraction_factor(int k) const {
  if (k <= 0 || k > dim_) k = dim_;
  if (k == 2) return contraction_factor_2d(a(0, 0), a(0, 1), a(1, 0), a(1, 1));
  return la::spectral_norm(la::block(*this, k), k);
}

std::optional<Point> AffineMap::fixed_point() const {
  la::Matrix m{};
  for (int r = 0; r < dim_; ++r)
    for (int c = 0; c < dim_; ++c) m[r][c] = (r == c ? 1.0 : 0.0) - a(r, c);
  la::Matrix inv;
  if (!la::invert(m, dim_, inv)) return std::nullopt;
  Point p{};
  for (int r = 0; r < dim_; ++r) {
    double v = 0.0;
    for (int c = 0; c < dim_; ++c) v += inv[r][c] * b(c);
    p[r] = v;
  }
  return p;
}

bool AffineMap::finite() const {
  for (int r = 0; r < dim_; ++r) {
    if (!std::isfinite(b(r))) return false;
    for (int c = 0; c < dim_; ++c)
      if (!std::isfinite(a(r, c))) return false;
  }
  return true;
}

double contraction_factor_2d(double a11, double a12, double a21, double a22) {
  // Eq. 8-9: the largest singular value of [[a11, a12], [a21, a22]].
  const double alpha = (a11 * a11 + a21 * a21) / 2.0;
  const double beta = (a12 * a12 + a22 * a22) / 2.0;
  const double gamma = a11 * a12 + a21 * a22;
  return std::sqrt(alpha + beta + std::sqrt((alpha - beta) * (alpha - beta) + gamma * gamma));
}

}  // namespace ifsforge
