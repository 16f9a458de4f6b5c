#include "ifsforge/render/recursion.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "ifsforge/core/error.h"
#include "ifsforge/render/parameters.h"

namespace ifsforge {

void check_leaf_count(std::size_t maps, int depth) {
  if (maps < 2 || depth <= 0) return;
  const double log_leaves = depth * std::log(static_cast<double>(maps));
  if (log_leaves > std::log(static_cast<double>(kMaxIterations)))
    throw InputError("depth: " + std::to_string(maps) + "^" + std::to_string(depth) + " = 10^" +
                     std::to_string(static_cast<int>(log_leaves / std::log(10.0))) +
                     " leaves, more than 10^12; choose a smaller depth, or 0 (automatic)");
}

RecursionPlan plan_recursion(const Ifs& ifs, int depth, int auto_depth) {
  check_leaf_count(ifs.size(), depth);
  RecursionPlan plan;
  plan.max_depth = std::clamp(depth > 0 ? depth : auto_depth, 1, 64);
  const Bounds b = ifs.attractor_bounds(1u << 16);
  for (int c = 0; c < ifs.dim(); ++c) {
    const double extent = b.hi[c] - b.lo[c];
    // The sample may miss the attractor's far tips: grow the box a little.
    const double margin = 0.02 * extent + 1e-12 * (std::abs(b.lo[c]) + std::abs(b.hi[c]));
    plan.center.push_back(0.5 * (b.lo[c] + b.hi[c]));
    plan.half.push_back(0.5 * extent + margin);
  }
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
