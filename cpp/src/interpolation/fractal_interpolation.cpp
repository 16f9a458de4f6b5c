#include "ifsforge/interpolation/fractal_interpolation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/interpolation/grid_recursion.h"
#include "ifsforge/interpolation/vertical_scaling.h"

namespace ifsforge {

FractalInterpolation::FractalInterpolation(std::vector<double> x, std::vector<double> values,
                                           std::vector<double> vertical_scaling)
    : x_(std::move(x)), values_(std::move(values)), a22_(std::move(vertical_scaling)) {
  if (x_.size() != values_.size())
    throw InputError("fractal interpolation: " + std::to_string(x_.size()) + " x values but " +
                     std::to_string(values_.size()) + " data values");
  if (x_.size() < 3)
    throw InputError("fractal interpolation needs at least 3 data points (2 maps), got " + std::to_string(x_.size()));
  const std::size_t n = x_.size() - 1;
  for (std::size_t i = 0; i <= n; ++i) {
    if (!std::isfinite(x_[i])) throw InputError("fractal interpolation: x[" + std::to_string(i) + "] is not finite");
    if (!std::isfinite(values_[i]))
      throw InputError("fractal interpolation: value[" + std::to_string(i) + "] is not finite");
    if (i > 0 && !(x_[i] > x_[i - 1])) {
      std::ostringstream s;
      s << "fractal interpolation: x must increase strictly (Eq. 90), but x[" << i << "] = " << x_[i] << " <= x["
        << i - 1 << "] = " << x_[i - 1];
      throw InputError(s.str());
    }
  }
  if (a22_.size() == 1) a22_.assign(n, a22_[0]);
  if (a22_.size() != n)
    throw InputError("fractal interpolation: " + std::to_string(n + 1) + " data points need " + std::to_string(n) +
                     " vertical scaling factors (or one for all), got " + std::to_string(a22_.size()));
  check_vertical_scaling(a22_, "fractal interpolation: a22");

  const double x0 = x_.front(), width = x_.back() - x_.front();
  nodes_.resize(n + 1);
  equally_spaced_ = true;
  for (std::size_t i = 0; i <= n; ++i) {
    nodes_[i] = (x_[i] - x0) / width;
    equally_spaced_ &= std::fabs(nodes_[i] - double(i) / double(n)) <= 1e-12;
  }
  nodes_.back() = 1.0;
  // Eq. 94 with x_0 = 0, x_N = 1: the maps send [0, 1] onto [v_{i}, v_{i+1}].
  a21_.resize(n);
  b2_.resize(n);
  double largest = 0.0, deviation = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    a21_[i] = values_[i + 1] - values_[i] - a22_[i] * (values_[n] - values_[0]);
    b2_[i] = values_[i] - a22_[i] * values_[0];
    largest = std::max(largest, std::fabs(a22_[i]));
    // e = f - p obeys e(L_i v) = [c_i(v) + a22_i p(v) - p(L_i v)] + a22_i e(v); the bracket is
    // piecewise linear with corners at the nodes, so its maximum is at a node.
    for (std::size_t j = 0; j <= n; ++j) {
      const double mapped = a21_[i] * nodes_[j] + b2_[i] + a22_[i] * values_[j];
      const double chord = values_[i] + (values_[i + 1] - values_[i]) * nodes_[j];
      deviation = std::max(deviation, std::fabs(mapped - chord));
    }
  }
  deviation_bound_ = deviation / (1.0 - largest);
}

AffineMap FractalInterpolation::map(std::size_t i) const {
  if (i >= maps()) throw InputError("fractal interpolation: no map " + std::to_string(i));
  // Eq. 94, with the seed's misprint corrected: b2 takes x_N F_{i-1} - x_0 F_i.
  const double x0 = x_.front(), xn = x_.back(), f0 = values_.front(), fn = values_.back();
  const double w = xn - x0, d = a22_[i];
  const double a11 = (x_[i + 1] - x_[i]) / w;
  const double b1 = (xn * x_[i] - x0 * x_[i + 1]) / w;
  const double a21 = (values_[i + 1] - values_[i]) / w - d * (fn - f0) / w;
  const double b2 = (xn * values_[i] - x0 * values_[i + 1]) / w - d * (xn * f0 - x0 * fn) / w;
  return AffineMap(2, {a11, 0.0, a21, d}, {b1, b2});
}

Ifs FractalInterpolation::to_ifs(std::string name) const {
  std::vector<AffineMap> maps;
  std::vector<double> probabilities;
  for (std::size_t i = 0; i < this->maps(); ++i) {
    maps.push_back(map(i));
    probabilities.push_back(maps.back().a(0, 0));
  }
  Ifs ifs(std::move(name), ChannelLayout("xy"), std::move(maps), std::move(probabilities));
  const std::vector<double> graph = sample(1025);
  const auto [lo, hi] = std::minmax_element(graph.begin(), graph.end());
  const double margin_x = 0.03 * (x_.back() - x_.front());
  const double margin_y = 0.03 * std::max(*hi - *lo, 1e-9 * std::max(1.0, std::fabs(*hi)));
  RenderDefaults defaults;
  defaults.window = {x_.front() - margin_x, *lo - margin_y, x_.back() + margin_x, *hi + margin_y};
  defaults.algorithm = "chaos";
  ifs.set_render_defaults(defaults);
  std::ostringstream description;
  description << "Fractal interpolation (Eq. 94) of " << x_.size() << " points; a22 =";
  for (double d : a22_) description << ' ' << d;
  ifs.set_description(description.str());
  return ifs;
}

double FractalInterpolation::linear(double v) const {
  const std::size_t n = maps();
  std::size_t i = std::upper_bound(nodes_.begin(), nodes_.end(), v) - nodes_.begin();
  i = std::clamp<std::size_t>(i, 1, n) - 1;
  const double t = (v - nodes_[i]) / (nodes_[i + 1] - nodes_[i]);
  return values_[i] + (values_[i + 1] - values_[i]) * t;
}

double FractalInterpolation::evaluate(double x) const {
  if (!(x >= x_.front() && x <= x_.back())) {
    std::ostringstream s;
    s << "fractal interpolation: x = " << x << " is outside the data range [" << x_.front() << ", " << x_.back()
      << "]";
    throw InputError(s.str());
  }
  const auto exact = std::lower_bound(x_.begin(), x_.end(), x);
  if (*exact == x) return values_[exact - x_.begin()];
  const auto [lo, hi] = std::minmax_element(values_.begin(), values_.end());
  const double tolerance = 1e-14 * std::max(*hi - *lo, std::fabs(*hi) + std::fabs(*lo));
  const std::size_t n = maps();
  double v = (x - x_.front()) / (x_.back() - x_.front());
  double sum = 0.0, factor = 1.0;
  // f(v) = c_i(u) + a22_i f(u) with v = L_i(u): unroll until the rest cannot matter.
  for (;;) {
    const auto node = std::lower_bound(nodes_.begin(), nodes_.end(), v);
    if (node != nodes_.end() && *node == v) return sum + factor * values_[node - nodes_.begin()];
    if (std::fabs(factor) * deviation_bound_ <= tolerance) return sum + factor * linear(v);
    std::size_t i = std::clamp<std::size_t>(node - nodes_.begin(), 1, n) - 1;
    const double u = std::clamp((v - nodes_[i]) / (nodes_[i + 1] - nodes_[i]), 0.0, 1.0);
    sum += factor * (a21_[i] * u + b2_[i]);
    factor *= a22_[i];
    v = u;
  }
}

std::vector<double> FractalInterpolation::evaluate(const std::vector<double>& xs) const {
  std::vector<double> out;
  out.reserve(xs.size());
  for (double x : xs) out.push_back(evaluate(x));
  return out;
}

std::vector<double> FractalInterpolation::sample(std::size_t count) const {
  if (count < 2) throw InputError("fractal interpolation: sample() needs at least 2 points, got " + std::to_string(count));
  std::vector<double> out(count);
  if (equally_spaced_) {
    GridRecursion(maps(), count).evaluate(values_.data(), a22_.data(), out.data());
    return out;
  }
  const double x0 = x_.front(), w = x_.back() - x_.front();
  for (std::size_t t = 0; t < count; ++t) {
    const double x = t + 1 == count ? x_.back() : x0 + w * (double(t) / double(count - 1));
    out[t] = evaluate(x);
  }
  return out;
}

double FractalInterpolation::dimension() const {
  double total = 0.0;
  for (double d : a22_) total += std::fabs(d);
  // Collinear data: the line itself is the fixed point, whatever the a22.
  const double f0 = values_.front(), fn = values_.back();
  const auto [lo, hi] = std::minmax_element(values_.begin(), values_.end());
  bool collinear = true;
  for (std::size_t i = 0; i < values_.size(); ++i)
    collinear &= std::fabs(values_[i] - (f0 + (fn - f0) * nodes_[i])) <= 1e-12 * std::max(1.0, *hi - *lo);
  if (total <= 1.0 || collinear) return 1.0;
  // sum |a22_i| a11_i^(D-1) decreases from sum |a22_i| > 1 at D = 1 to below 1 at D = 2.
  auto excess = [&](double d) {
    double s = 0.0;
    for (std::size_t i = 0; i < maps(); ++i) s += std::fabs(a22_[i]) * std::pow(nodes_[i + 1] - nodes_[i], d - 1.0);
    return s - 1.0;
  };
  double a = 1.0, b = 2.0;
  for (int k = 0; k < 60; ++k) {
    const double m = 0.5 * (a + b);
    (excess(m) > 0 ? a : b) = m;
  }
  return 0.5 * (a + b);
}

}  // namespace ifsforge
