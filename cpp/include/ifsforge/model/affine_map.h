#pragma once
/// @file An affine map x' = A x + b on R^n, 1 <= n <= kMaxDim (seed Eq. 2 and Eq. 19).
#include <array>
#include <optional>
#include <vector>

namespace ifsforge {

constexpr int kMaxDim = 8;
using Point = std::array<double, kMaxDim>;

/// Readers refuse a coefficient larger than this in magnitude: no useful map stretches by 10^9,
/// and iterating one soon overflows to infinity far from the file that held it.
constexpr double kMaxCoefficient = 1e9;

class AffineMap {
 public:
  AffineMap() = default;
  /// @brief The identity on R^dim.
  explicit AffineMap(int dim);
  /// @brief From a row-major dim x dim matrix and a dim-vector offset.
  AffineMap(int dim, const std::vector<double>& matrix, const std::vector<double>& offset);

  int dim() const { return dim_; }
  double a(int row, int col) const { return a_[row * kMaxDim + col]; }
  double& a(int row, int col) { return a_[row * kMaxDim + col]; }
  double b(int row) const { return b_[row]; }
  double& b(int row) { return b_[row]; }
  std::vector<double> matrix() const;  ///< row-major dim x dim
  std::vector<double> offset() const;

  void apply(const double* in, double* out) const {
    for (int r = 0; r < dim_; ++r) {
      double v = b_[r];
      for (int c = 0; c < dim_; ++c) v += a_[r * kMaxDim + c] * in[c];
      out[r] = v;
    }
  }
  Point operator()(const Point& p) const {
    Point q{};
    apply(p.data(), q.data());
    return q;
  }

  /// @brief (*this) o inner: x -> A (A' x + b') + b.
  AffineMap compose(const AffineMap& inner) const;
  /// @brief out = (*this) o inner in place, out distinct from both (out's coefficients
  /// beyond dim stay zero): a recursion composes one map per node without building one.
  void compose_into(const AffineMap& inner, AffineMap& out) const;
  /// @brief The inverse map, or nothing when A is singular.
  std::optional<AffineMap> inverse() const;
  /// @brief det of the leading k x k block (k = dim by default): |det| is the Jacobian (Eq. 46).
  double determinant(int k = 0) const;
  /// @brief Spectral norm of the leading k x k block (k = dim by default); in 2D it equals
  /// Eq. 8-9's s = sqrt(alpha + beta + sqrt((alpha - beta)^2 + gamma^2)).
  double contraction_factor(int k = 0) const;
  /// @brief The point with A x + b = x, or nothing when 1 is an eigenvalue of A.
  std::optional<Point> fixed_point() const;
  /// @brief True when every coefficient is finite.
  bool finite() const;

 private:
  int dim_ = 0;
  std::array<double, kMaxDim * kMaxDim> a_{};
  std::array<double, kMaxDim> b_{};
};

/// @brief Eq. 8-9 verbatim: the contraction factor of a 2 x 2 linear part.
double contraction_factor_2d(double a11, double a12, double a21, double a22);

}  // namespace ifsforge
