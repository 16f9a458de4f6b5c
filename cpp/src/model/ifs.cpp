#include "ifsforge/model/ifs.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/attractor_points.h"
#include "ifsforge/model/map_sampler.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/model/probabilities.h"
#include "affine_walk.h"

namespace ifsforge {

std::vector<double> jacobian_probabilities(const std::vector<AffineMap>& maps, int spatial_dims) {
  std::vector<double> p(maps.size());
  double largest = 0.0;
  for (std::size_t i = 0; i < maps.size(); ++i) {
    p[i] = std::abs(maps[i].determinant(spatial_dims));
    largest = std::max(largest, p[i]);
  }
  if (!(largest > 0.0)) return std::vector<double>(maps.size(), 1.0 / maps.size());
  double total = 0.0;
  for (double& v : p) total += (v = std::max(v, 0.01 * largest));
  for (double& v : p) v /= total;
  return p;
}

Ifs::Ifs(std::string name, ChannelLayout layout, std::vector<AffineMap> maps,
         std::vector<double> probabilities)
    : name_(std::move(name)), layout_(std::move(layout)), maps_(std::move(maps)) {
  if (maps_.empty()) throw InputError("a system needs at least one map");
  for (std::size_t i = 0; i < maps_.size(); ++i) {
    const std::string which = "map " + std::to_string(i + 1);
    if (maps_[i].dim() != layout_.dim())
      throw InputError(which + " is " + std::to_string(maps_[i].dim()) + "D but the layout '" +
                       layout_.text() + "' has " + std::to_string(layout_.dim()) + " dimensions");
    if (!maps_[i].finite()) throw InputError(which + " has a coefficient that is NaN or infinite");
  }
  if (probabilities.empty()) {
    probabilities_ = jacobian_probabilities(maps_, layout_.spatial_dims());
    return;
  }
  if (probabilities.size() != maps_.size())
    throw InputError(std::to_string(probabilities.size()) + " probabilities for " +
                     std::to_string(maps_.size()) + " maps");
  double total = 0.0;
  for (std::size_t i = 0; i < probabilities.size(); ++i) {
    const double p = probabilities[i];
    if (!std::isfinite(p) || p < 0.0)
      throw InputError("the probability of map " + std::to_string(i + 1) +
                       " must be a finite number >= 0");
    total += p;
  }
  if (!(total > 0.0)) throw InputError("the probabilities must sum to a positive number");
  probabilities_ = std::move(probabilities);
  normalise_probabilities(probabilities_, total);
}

void normalise_probabilities(double* probabilities, std::size_t count, double total) {
  const double rounding = 2.0 * double(count) * std::numeric_limits<double>::epsilon();
  if (std::abs(total - 1.0) <= rounding) return;
  for (std::size_t i = 0; i < count; ++i) probabilities[i] /= total;
}

std::vector<double> Ifs::contraction_factors() const {
  std::vector<double> s;
  for (const auto& m : maps_) s.push_back(m.contraction_factor());
  return s;
}

std::vector<double> Ifs::spatial_contraction_factors() const {
  std::vector<double> s;
  for (const auto& m : maps_) s.push_back(m.contraction_factor(spatial_dims()));
  return s;
}

double Ifs::contraction_ratio() const {
  const auto s = contraction_factors();
  return *std::max_element(s.begin(), s.end());
}

double Ifs::average_log_contraction() const {
  const auto s = contraction_factors();
  double sum = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (probabilities_[i] == 0.0) continue;
    if (s[i] == 0.0) return -std::numeric_limits<double>::infinity();
    sum += probabilities_[i] * std::log(s[i]);
  }
  return sum;
}

double Ifs::lyapunov_exponent(std::size_t steps, std::uint64_t seed) const {
  // Furstenberg-Kesten: (1/n) log |A_k(n) ... A_k(1) v| for a random unit vector v.
  // The products follow the maps' chain (a recurrent system's transitions).
  Rng rng(seed, 0);
  const MapChain chain(*this);
  const int n = dim();
  Point v{}, w{};
  auto reset = [&] {
    for (int i = 0; i < n; ++i) v[i] = rng.uniform() - 0.5;
  };
  reset();
  std::uint32_t state = chain.start(rng);
  double sum = 0.0;
  for (std::size_t step = 0; step < steps; ++step) {
    state = chain.next(state, rng.next());
    const AffineMap& m = maps_[state];
    double norm = 0.0;
    for (int r = 0; r < n; ++r) {
      double x = 0.0;
      for (int c = 0; c < n; ++c) x += m.a(r, c) * v[c];
      w[r] = x;
      norm += x * x;
    }
    if (norm == 0.0) return -std::numeric_limits<double>::infinity();
    norm = std::sqrt(norm);
    sum += std::log(norm);
    for (int i = 0; i < n; ++i) v[i] = w[i] / norm;
  }
  return sum / static_cast<double>(steps);
}

Classification Ifs::classify() const {
  const auto s = contraction_factors();
  if (polar()) {
    // Eq. 30 bounds each polar map's orbit about its centre; contracting affine maps beside
    // them keep every orbit in a bounded disc too.
    for (std::size_t i = 0; i < s.size(); ++i)
      if (!polar_[i] && !(s[i] < 1.0)) return Classification::Divergent;
    return Classification::LocallyContractive;
  }
  if (*std::max_element(s.begin(), s.end()) < 1.0) return Classification::Hyperbolic;
  if (average_log_contraction() < 0.0) return Classification::AverageContractive;
  // A small margin keeps borderline systems (lambda ~ 0, e.g. a pure rotation) out.
  if (lyapunov_exponent() < -1e-3) return Classification::EventuallyContractive;
  return Classification::Divergent;
}

void Ifs::require_attractor() const {
  if (classify() != Classification::Divergent) return;
  const auto s = contraction_factors();
  std::string detail;
  for (std::size_t i = 0; i < s.size(); ++i)
    detail += (i ? ", " : "") + std::to_string(s[i]).substr(0, 6);
  throw DivergentSystemError("system '" + name_ +
                             "' is divergent: it has no attractor (contraction factors " + detail +
                             "; sum p_i log s_i = " + std::to_string(average_log_contraction()) +
                             " is not below 0, Eq. 14)");
}

std::vector<Point> Ifs::fixed_points() const {
  std::vector<Point> points;
  for (const auto& m : maps_) {
    auto p = m.fixed_point();
    Point q{};
    q.fill(std::numeric_limits<double>::quiet_NaN());
    points.push_back(p ? *p : q);
  }
  return points;
}

Point Ifs::start_point() const {
  // A fixed point of a contractive map lies on the attractor: prefer the most probable one.
  std::size_t best = maps_.size();
  for (std::size_t i = 0; i < maps_.size(); ++i)
    if (maps_[i].contraction_factor() < 1.0 && maps_[i].fixed_point() &&
        (best == maps_.size() || probabilities_[i] > probabilities_[best]))
      best = i;
  Point p{};
  if (best < maps_.size()) return *maps_[best].fixed_point();
  // No contractive map: walk to the attractor from the origin.
  Rng rng(0x5eed, 0);
  const MapChain chain(*this);
  std::uint32_t state = chain.start(rng);
  for (int i = 0; i < 1000; ++i) p = maps_[state = chain.next(state, rng.next())](p);
  return p;
}

namespace {

/// Orbit's walk (model/orbit.h) for an affine system of dimension N (affine_walk.h): the
/// frame, the plan's box and a volume's bounds walk 2^15-2^16 steps before any parallel work,
/// where the general step and a call per point through std::function took three times as long.
template <int N, class Visit>
void walk_affine(const Ifs& ifs, std::size_t count, std::uint64_t seed, Visit& visit) {
  const affine_walk::Walker<N> walker(ifs);
  const MapChain chain(ifs);
  Rng rng(seed, 0);
  std::uint32_t map = chain.start(rng);
  Point p = affine_walk::start(ifs, N);
  for (std::size_t i = 0; i < affine_walk::kSettle; ++i) walker.step(chain, rng, map, p);
  for (std::size_t s = 0; s < count; ++s) {
    walker.step(chain, rng, map, p);
    if (!walker.finite(p)) Orbit(ifs, chain, seed, 0, p).require_finite();  // its error, naming the system
    visit(static_cast<const Point&>(p));
  }
}

/// sample_attractor with `visit` inlined (2D and 3D affine systems by walk_affine).
template <class Visit>
void walk_samples(const Ifs& ifs, std::size_t count, std::uint64_t seed, Visit&& visit) {
  if (!ifs.polar() && ifs.dim() == 2) return walk_affine<2>(ifs, count, seed, visit);
  if (!ifs.polar() && ifs.dim() == 3) return walk_affine<3>(ifs, count, seed, visit);
  const MapChain chain(ifs);
  Orbit orbit(ifs, chain, seed, 0);
  orbit.skip(100);
  for (std::size_t s = 0; s < count; ++s) {
    orbit.step();
    orbit.require_finite();
    visit(orbit.point());
  }
}

}  // namespace

void sample_attractor(const Ifs& ifs, std::size_t count, std::uint64_t seed,
                      const std::function<void(const Point&)>& visit) {
  walk_samples(ifs, count, seed, visit);
}

Bounds Ifs::attractor_bounds(std::size_t samples, int threads) const {
  require_attractor();
  const Classification kind = classify();
  const bool hyperbolic = kind == Classification::Hyperbolic;
  // Polar systems stay in a bounded disc (Eq. 30): their support's extent is the samples' own.
  const bool bounded = hyperbolic || kind == Classification::LocallyContractive;
  if (!bounded) samples = std::min<std::size_t>(samples, 1u << 18);
  const int n = dim();
  Bounds b{std::vector<double>(n, std::numeric_limits<double>::infinity()),
           std::vector<double>(n, -std::numeric_limits<double>::infinity())};
  std::vector<std::vector<double>> values(bounded ? 0 : n);
  if (bounded) {
    sample_extent(*this, samples, 0xB0B5, n, [n](const Point& p, double* v) { std::copy(p.begin(), p.begin() + n, v); },
                  b.lo.data(), b.hi.data(), threads);
  } else {
    walk_samples(*this, samples, 0xB0B5, [&](const Point& p) {
      for (int c = 0; c < n; ++c) values[c].push_back(p[c]);
    });
  }
  for (int c = 0; c < static_cast<int>(values.size()); ++c) {
    b.lo[c] = quantile(values[c], 0.001);
    b.hi[c] = quantile(values[c], 0.999);
  }
  if (hyperbolic)
    for (const Point& p : attractor_extremes(*this))
      for (int c = 0; c < n; ++c) {
        b.lo[c] = std::min(b.lo[c], p[c]);
        b.hi[c] = std::max(b.hi[c], p[c]);
      }
  return b;
}

double quantile(std::vector<double>& values, double q) {
  const std::size_t k = std::min(values.size() - 1, static_cast<std::size_t>(q * values.size()));
  // The ends (a hyperbolic frame's 0 and 1) by one scan: partitioning took a few times as long,
  // on one core before every render's parallel work.
  if (k == 0) return *std::min_element(values.begin(), values.end());
  if (k + 1 == values.size()) return *std::max_element(values.begin(), values.end());
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace ifsforge
