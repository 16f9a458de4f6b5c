#include "ifsforge/render/recursion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "ifsforge/core/error.h"
#include "ifsforge/render/parameters.h"

namespace ifsforge {

namespace {

/// The smallest box B with AABB(w_i(B)) inside B for every map, from `start`: the fixed point
/// of B -> hull of the AABBs of w_i(B), a contraction when every map shrinks boxes (row sums
/// of |A| below 1). It holds the attractor, tightly for axis-aligned maps, and the boxes of
/// the pieces w_a(B) nest. False when the iteration does not settle.
bool invariant_box(const Ifs& ifs, std::vector<double>& lo, std::vector<double>& hi) {
  const int n = ifs.dim();
  for (const auto& m : ifs.maps())
    for (int r = 0; r < n; ++r) {
      double row = 0.0;
      for (int c = 0; c < n; ++c) row += std::abs(m.a(r, c));
      if (!(row < 1.0)) return false;
    }
  std::vector<double> center(n), half(n), next_lo(n), next_hi(n);
  for (int iteration = 0; iteration < 4000; ++iteration) {
    for (int c = 0; c < n; ++c) {
      center[c] = 0.5 * (lo[c] + hi[c]);
      half[c] = 0.5 * (hi[c] - lo[c]);
    }
    std::fill(next_lo.begin(), next_lo.end(), std::numeric_limits<double>::infinity());
    std::fill(next_hi.begin(), next_hi.end(), -std::numeric_limits<double>::infinity());
    for (const auto& m : ifs.maps())
      for (int r = 0; r < n; ++r) {
        double c0 = m.b(r), h = 0.0;
        for (int c = 0; c < n; ++c) {
          c0 += m.a(r, c) * center[c];
          h += std::abs(m.a(r, c)) * half[c];
        }
        next_lo[r] = std::min(next_lo[r], c0 - h);
        next_hi[r] = std::max(next_hi[r], c0 + h);
      }
    double change = 0.0, size = 0.0;
    for (int c = 0; c < n; ++c) {
      change = std::max({change, std::abs(next_lo[c] - lo[c]), std::abs(next_hi[c] - hi[c])});
      size = std::max(size, next_hi[c] - next_lo[c]);
    }
    lo.swap(next_lo);
    hi.swap(next_hi);
    if (change <= 1e-14 * (1.0 + size)) return true;
  }
  return false;
}

}  // namespace

void piece_box(const Ifs& ifs, const Bounds& bounds, double margin, bool any_invariant, std::vector<double>& center,
               std::vector<double>& half) {
  const int n = ifs.dim(), spatial = ifs.spatial_dims();
  std::vector<double> lo(n), hi(n);
  for (int c = 0; c < n; ++c) {
    const double extent = bounds.hi[c] - bounds.lo[c];
    lo[c] = bounds.lo[c] - margin * extent;
    hi[c] = bounds.hi[c] + margin * extent;
  }
  // The invariant box of `system` on rows [0, rows); unless `any_invariant`, only when it lies
  // inside the grown bounds.
  auto take = [&](const Ifs& system, int rows) {
    std::vector<double> l(bounds.lo.begin(), bounds.lo.begin() + rows), h(bounds.hi.begin(), bounds.hi.begin() + rows);
    if (!invariant_box(system, l, h)) return false;
    for (int r = 0; r < rows && !any_invariant; ++r)
      if (l[r] < lo[r] || h[r] > hi[r]) return false;
    std::copy(l.begin(), l.end(), lo.begin());
    std::copy(h.begin(), h.end(), hi.begin());
    return true;
  };
  // Without one, the spatial rows alone may have one (a gray channel that reads x, y, z):
  // exact spatial boxes keep a grid-aligned fractal's pieces on cell faces.
  if (ifs.classify() == Classification::Hyperbolic && !take(ifs, n) && n > spatial) {
    std::vector<AffineMap> maps;
    bool independent = true;
    for (const auto& m : ifs.maps()) {
      AffineMap s(spatial);
      for (int r = 0; r < spatial; ++r) {
        for (int c = 0; c < spatial; ++c) s.a(r, c) = m.a(r, c);
        for (int c = spatial; c < n; ++c) independent = independent && m.a(r, c) == 0.0;
        s.b(r) = m.b(r);
      }
      maps.push_back(s);
    }
    if (independent) take(Ifs(ifs.name(), ChannelLayout(spatial == 2 ? "xy" : "xyz"), maps, ifs.probabilities()), spatial);
  }
  center.clear();
  half.clear();
  for (int c = 0; c < n; ++c) {
    center.push_back(0.5 * (lo[c] + hi[c]));
    half.push_back(0.5 * (hi[c] - lo[c]) + 1e-12 * std::abs(center.back()));
  }
}

void check_leaf_count(std::size_t maps, int depth) {
  if (maps < 2 || depth <= 0) return;
  const double log_leaves = depth * std::log(static_cast<double>(maps));
  if (log_leaves > std::log(static_cast<double>(kMaxIterations)))
    throw InputError("depth: " + std::to_string(maps) + "^" + std::to_string(depth) + " = 10^" +
                     std::to_string(static_cast<int>(log_leaves / std::log(10.0))) +
                     " leaves, more than 10^12; choose a smaller depth, or 0 (automatic)");
}

RecursionPlan plan_recursion(const Ifs& ifs, int depth, int auto_depth, int threads) {
  check_leaf_count(ifs.size(), depth);
  RecursionPlan plan;
  plan.max_depth = std::clamp(depth > 0 ? depth : auto_depth, 1, 64);
  // A rotating map's invariant box (the fern's) is half as wide again as its attractor: the
  // deeper tree it asks for ran past the node budget. Only a tight one is taken.
  piece_box(ifs, ifs.attractor_bounds(1u << 16, threads), kPieceBoxMargin, false, plan.center, plan.half);
  const std::uint64_t n = ifs.size();
  if (n > 1) {
    double below = std::pow(static_cast<double>(n), plan.max_depth);
    while (plan.prefix < plan.max_depth && plan.jobs * n <= (1u << 24) &&
           (plan.jobs < 64 || (depth > 0 && below > (1u << 20)))) {
      ++plan.prefix;
      plan.jobs *= n;
      below /= static_cast<double>(n);
    }
  }
  return plan;
}

std::vector<std::uint32_t> job_address(const Ifs& ifs, const RecursionPlan& plan, std::uint64_t job) {
  if (!plan.addresses.empty()) return plan.addresses[job];
  std::vector<std::uint32_t> digits(static_cast<std::size_t>(plan.prefix));
  for (int level = plan.prefix - 1; level >= 0; --level, job /= ifs.size())
    digits[static_cast<std::size_t>(level)] = static_cast<std::uint32_t>(job % ifs.size());
  return digits;
}

void balance_jobs(const Ifs& ifs, RecursionPlan& plan, const std::function<double(const AffineMap&)>& weight) {
  constexpr std::size_t kMinJobs = 64, kMaxJobs = std::size_t(1) << 14;
  constexpr double kMaxShare = 1.0 / 256.0;
  const std::size_t n = ifs.size();
  if (n < 2) return;
  struct Piece {
    std::vector<std::uint32_t> address;
    AffineMap map;
    double weight;
    bool split;
  };
  std::vector<Piece> pieces;
  auto lighter = [&](std::size_t a, std::size_t b) {
    return pieces[a].weight < pieces[b].weight || (pieces[a].weight == pieces[b].weight && a > b);
  };
  std::priority_queue<std::size_t, std::vector<std::size_t>, decltype(lighter)> heaviest(lighter);
  auto add = [&](std::vector<std::uint32_t> address, AffineMap map) {
    const double w = weight(map);
    pieces.push_back({std::move(address), std::move(map), std::isfinite(w) ? std::max(w, 0.0) : 0.0, false});
    heaviest.push(pieces.size() - 1);
  };
  add({}, AffineMap(ifs.dim()));
  const double root = pieces[0].weight;
  std::size_t jobs = 1;
  while (!heaviest.empty() && jobs + n - 1 <= kMaxJobs) {
    const std::size_t top = heaviest.top();
    if (jobs >= kMinJobs && pieces[top].weight <= kMaxShare * root) break;
    heaviest.pop();
    // A piece at the deepest level stays one job, as does one outside the image (weight 0)
    // once there are enough jobs.
    if (static_cast<int>(pieces[top].address.size()) + 1 >= plan.max_depth ||
        (jobs >= kMinJobs && !(pieces[top].weight > 0.0)))
      continue;
    pieces[top].split = true;
    const std::vector<std::uint32_t> address = pieces[top].address;
    const AffineMap map = pieces[top].map;
    for (std::uint32_t i = 0; i < n; ++i) {
      std::vector<std::uint32_t> child = address;
      child.push_back(i);
      add(std::move(child), map.compose(ifs.map(i)));
    }
    jobs += n - 1;
  }
  plan.addresses.clear();
  for (Piece& p : pieces)
    if (!p.split) plan.addresses.push_back(std::move(p.address));
  std::sort(plan.addresses.begin(), plan.addresses.end());
  plan.jobs = plan.addresses.size();
}

int depth_for_size(const Ifs& ifs, const RecursionPlan& plan, double size, int extra, int fallback) {
  const auto s = ifs.contraction_factors();
  const double largest = *std::max_element(s.begin(), s.end());
  double radius = 0.0;
  for (double h : plan.half) radius += h * h;
  radius = std::sqrt(radius);
  if (!(largest < 1.0) || !(size > 0.0)) return std::clamp(fallback, 1, 64);
  if (largest == 0.0 || radius <= size) return std::clamp(1 + extra, 1, 64);
  const int needed = static_cast<int>(std::ceil(std::log(size / radius) / std::log(largest)));
  return std::clamp(std::max(needed + extra, fallback), 1, 64);
}

}  // namespace ifsforge
