#pragma once
/// @file Fractal interpolation functions (seed 6.1.3.2, Eq. 90-94): the continuous function
/// whose graph is the attractor of N maps w_i(x, y) = (a11_i x + b1_i, a21_i x + a22_i y + b2_i)
/// fixed by the data (x_i, F_i), i = 0..N, and the free vertical scaling factors a22_i.
#include <string>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

class FractalInterpolation {
 public:
  /// @brief Eq. 90: x_0 < x_1 < ... < x_N (N >= 2, strictly increasing, finite), F_i finite,
  /// and a22_i for the maps i = 1..N (one value: the same for every map) with |a22_i| < 1.
  /// InputError names the first offending entry.
  FractalInterpolation(std::vector<double> x, std::vector<double> values, std::vector<double> vertical_scaling);

  std::size_t maps() const { return a22_.size(); }
  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& values() const { return values_; }
  const std::vector<double>& vertical_scaling() const { return a22_; }
  /// @brief True when the nodes are equally spaced (to 1e-12 of the range): then sample()
  /// runs the exact grid recursion.
  bool equally_spaced() const { return equally_spaced_; }

  /// @brief Map i (0-based; the seed's w_{i+1}) from Eq. 94 on the data's own range.
  AffineMap map(std::size_t i) const;
  /// @brief The interpolation IFS on layout "xy" (probabilities proportional to a11_i, so
  /// random iteration covers the graph evenly in x).
  Ifs to_ifs(std::string name = "fractal interpolation") const;

  /// @brief f(x) for x in [x_0, x_N], deterministic and exact to 1e-14 of the data range: the
  /// fixed-point equation f(L_i(u)) = a21_i u + b2_i + a22_i f(u) is unrolled until the
  /// accumulated factor times a bound of |f - (piecewise-linear interpolant)| is negligible.
  /// Data nodes return F_i exactly. InputError outside [x_0, x_N].
  /// @note A rough graph is only Holder continuous: when an inverse map L_i^-1 is not exact
  /// in floating point (spacings that are not powers of two of the range), the orbit of x is
  /// that of a point within rounding of x, and f there may differ by far more than 1e-14.
  /// sample() on equally spaced nodes works on exact grid positions and has no such limit.
  double evaluate(double x) const;
  std::vector<double> evaluate(const std::vector<double>& xs) const;
  /// @brief f at `count` >= 2 equally spaced points from x_0 to x_N (both included): the exact
  /// grid recursion when the nodes are equally spaced, evaluate() per point otherwise.
  std::vector<double> sample(std::size_t count) const;

  /// @brief Box-counting dimension of the graph (Barnsley): the D with
  /// sum_i |a22_i| a11_i^(D-1) = 1 when sum_i |a22_i| > 1 and the data are not collinear,
  /// else 1. For equally spaced nodes D = 1 + log(sum_i |a22_i|) / log N.
  double dimension() const;

 private:
  std::vector<double> x_, values_, a22_;
  std::vector<double> nodes_;     ///< (x_i - x_0) / (x_N - x_0)
  std::vector<double> a21_, b2_;  ///< Eq. 94 on the normalised range [0, 1]
  double deviation_bound_ = 0.0;  ///< bound of |f - piecewise linear| (see evaluate)
  bool equally_spaced_ = false;

  double linear(double v) const;
};

}  // namespace ifsforge
