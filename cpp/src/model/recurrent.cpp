#include "ifsforge/model/recurrent.h"

#include <cmath>
#include <string>

#include "ifsforge/core/error.h"
#include "ifsforge/core/random.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/map_sampler.h"
#include "ifsforge/model/orbit.h"
#include "ifsforge/model/probabilities.h"

namespace ifsforge {
namespace {

/// States reachable from state 0 following the entries (i, j) > 0 (or (j, i) when `reverse`).
std::vector<bool> reachable(const std::vector<double>& p, std::size_t n, bool reverse) {
  std::vector<bool> seen(n, false);
  std::vector<std::size_t> stack{0};
  seen[0] = true;
  while (!stack.empty()) {
    const std::size_t i = stack.back();
    stack.pop_back();
    for (std::size_t j = 0; j < n; ++j) {
      const double entry = reverse ? p[j * n + i] : p[i * n + j];
      if (entry > 0.0 && !seen[j]) {
        seen[j] = true;
        stack.push_back(j);
      }
    }
  }
  return seen;
}

}  // namespace

TransitionMatrix::TransitionMatrix(std::size_t size, std::vector<double> row_major)
    : size_(size), p_(std::move(row_major)) {
  if (size == 0) throw InputError("a transition matrix needs at least one row");
  if (p_.size() != size * size)
    throw InputError("a transition matrix for " + std::to_string(size) + " maps has " +
                     std::to_string(size * size) + " entries, not " + std::to_string(p_.size()));
  for (std::size_t i = 0; i < size; ++i) {
    double total = 0.0;
    for (std::size_t j = 0; j < size; ++j) {
      const double v = p_[i * size + j];
      if (!std::isfinite(v) || v < 0.0)
        throw InputError("transition (" + std::to_string(i + 1) + ", " + std::to_string(j + 1) +
                         ") must be a finite number >= 0");
      total += v;
    }
    if (!(total > 0.0))
      throw InputError("row " + std::to_string(i + 1) + " of the transition matrix sums to 0: map " +
                       std::to_string(i + 1) + " must be followed by some map");
    normalise_probabilities(p_.data() + i * size, size, total);  // a fixed point: rows read back stay
  }
  const auto forward = reachable(p_, size, false), backward = reachable(p_, size, true);
  for (std::size_t i = 0; i < size; ++i)
    if (!forward[i] || !backward[i])
      throw InputError("the transition matrix is reducible: map " + std::to_string(i + 1) +
                       (forward[i] ? " cannot lead back to map 1" : " cannot be reached from map 1") +
                       " (a recurrent IFS needs a strongly connected transition graph)");
}

TransitionMatrix TransitionMatrix::independent(const std::vector<double>& probabilities) {
  TransitionMatrix t;
  t.size_ = probabilities.size();
  for (std::size_t i = 0; i < t.size_; ++i) t.p_.insert(t.p_.end(), probabilities.begin(), probabilities.end());
  return t;
}

std::vector<double> TransitionMatrix::row(std::size_t i) const {
  return std::vector<double>(p_.begin() + i * size_, p_.begin() + (i + 1) * size_);
}

std::vector<double> TransitionMatrix::stationary() const {
  // Solve m (P - I) = 0 with sum m = 1: the transposed system with its last equation replaced
  // by the normalization, by Gaussian elimination with partial pivoting.
  const std::size_t n = size_;
  std::vector<double> a(n * (n + 1), 0.0);
  for (std::size_t r = 0; r < n; ++r) {
    for (std::size_t c = 0; c < n; ++c) a[r * (n + 1) + c] = p_[c * n + r] - (r == c ? 1.0 : 0.0);
  }
  for (std::size_t c = 0; c <= n; ++c) a[(n - 1) * (n + 1) + c] = 1.0;
  for (std::size_t col = 0; col < n; ++col) {
    std::size_t pivot = col;
    for (std::size_t r = col + 1; r < n; ++r)
      if (std::abs(a[r * (n + 1) + col]) > std::abs(a[pivot * (n + 1) + col])) pivot = r;
    for (std::size_t c = 0; c <= n; ++c) std::swap(a[col * (n + 1) + c], a[pivot * (n + 1) + c]);
    const double d = a[col * (n + 1) + col];
    for (std::size_t r = 0; r < n; ++r) {
      if (r == col) continue;
      const double f = a[r * (n + 1) + col] / d;
      if (f == 0.0) continue;
      for (std::size_t c = col; c <= n; ++c) a[r * (n + 1) + c] -= f * a[col * (n + 1) + c];
    }
  }
  std::vector<double> m(n);
  double total = 0.0;
  for (std::size_t i = 0; i < n; ++i) total += (m[i] = std::max(0.0, a[i * (n + 1) + n] / a[i * (n + 1) + i]));
  for (double& v : m) v /= total;
  return m;
}

TransitionMatrix TransitionMatrix::reversed() const {
  const std::vector<double> m = stationary();
  TransitionMatrix r;
  r.size_ = size_;
  r.p_.assign(size_ * size_, 0.0);
  for (std::size_t j = 0; j < size_; ++j) {
    double total = 0.0;
    for (std::size_t i = 0; i < size_; ++i) total += (r.p_[j * size_ + i] = m[i] * p_[i * size_ + j]);
    for (std::size_t i = 0; i < size_ && total > 0.0; ++i) r.p_[j * size_ + i] /= total;
  }
  return r;
}

TransitionMatrix effective_transitions(const Ifs& ifs) {
  return ifs.recurrent() ? ifs.transitions() : TransitionMatrix::independent(ifs.probabilities());
}

std::vector<Point> piece_points(const Ifs& ifs) {
  const TransitionMatrix p = effective_transitions(ifs);
  const std::size_t n = ifs.size();
  const MapChain chain(ifs);
  std::vector<Point> points(n);
  std::vector<bool> found(n, false);
  Rng rng(0x91ECE5, 0);
  Point x = ifs.start_point();
  std::uint32_t state = MapSampler(ifs.probabilities())(rng.next());
  for (int step = 0; step < 4000; ++step) {
    state = chain.next(state, rng.next());
    x = ifs.map(state)(x);
    if (step >= 100) {
      points[state] = x;
      found[state] = true;
    }
  }
  // Pieces the walk missed (tiny probabilities): w_j of a point of a piece that may precede j.
  for (bool changed = true; changed;) {
    changed = false;
    for (std::size_t j = 0; j < n; ++j) {
      if (found[j]) continue;
      for (std::size_t i = 0; i < n && !found[j]; ++i)
        if (found[i] && p(i, j) > 0.0) {
          points[j] = ifs.map(j)(points[i]);
          found[j] = changed = true;
        }
    }
  }
  for (std::size_t j = 0; j < n; ++j)
    if (!found[j]) points[j] = ifs.map(j)(ifs.start_point());
  return points;
}

void Ifs::set_transitions(TransitionMatrix transitions) {
  if (transitions.empty()) {
    transitions_ = TransitionMatrix();
    return;
  }
  if (transitions.size() != maps_.size())
    throw InputError("system '" + name_ + "' has " + std::to_string(maps_.size()) + " maps but the transition matrix is " +
                     std::to_string(transitions.size()) + " x " + std::to_string(transitions.size()));
  if (!super_.empty() || !condensation_.empty() || polar())
    throw InputError("system '" + name_ + "': a recurrent system cannot also be a super IFS, have a condensation set or polar maps");
  probabilities_ = transitions.stationary();
  transitions_ = std::move(transitions);
}

}  // namespace ifsforge
