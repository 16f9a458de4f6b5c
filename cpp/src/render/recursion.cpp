#include "ifsforge/render/recursion.h"

#include <algorithm>
#include <cmath>

namespace ifsforge {
namespace {

bool spatial_rows_independent(const Ifs& ifs) {
  const int k = ifs.spatial_dims();
  for (const auto& m : ifs.maps())
    for (int r = 0; r < k; ++r)
      for (int c = k; c < ifs.dim(); ++c)
        if (m.a(r, c) != 0.0) return false;
  return true;
}

struct Walker {
  const Ifs& ifs;
  const RecursionPlan& plan;
  const std::function<void(const Point&, double, const std::uint32_t*, int)>& leaf;
  std::uint32_t address[256];

  bool stop(int length, double bound) const {
    return length >= plan.max_depth || (plan.cut > 0.0 && bound * plan.radius <= plan.cut);
  }

  void recurse(const Point& p, double mass, double bound, int length) {
    Point q;
    for (std::uint32_t i = 0; i < ifs.size(); ++i) {
      ifs.map(i).apply(p.data(), q.data());
      address[length] = i;
      const double m = mass * ifs.probabilities()[i], b = bound * plan.bound[i];
      if (stop(length + 1, b))
        leaf(q, m, address, length + 1);
      else
        recurse(q, m, b, length + 1);
    }
  }
};

}  // namespace

RecursionPlan plan_recursion(const Ifs& ifs, int depth, double cut, int fallback_depth) {
  RecursionPlan plan;
  const bool spatial = spatial_rows_independent(ifs);
  plan.bound = spatial ? ifs.spatial_contraction_factors() : ifs.contraction_factors();
  const double largest = *std::max_element(plan.bound.begin(), plan.bound.end());
  if (depth > 0) {
    plan.max_depth = depth;
  } else {
    // Deep enough for the cut to act along the least contractive branch (capped), or
    // Eq. 59's depth when some map does not contract.
    const int k = spatial ? ifs.spatial_dims() : ifs.dim();
    const Point start = ifs.start_point();
    sample_attractor(ifs, 1u << 15, 0x7AD1, [&](const Point& q) {
      double d = 0.0;
      for (int c = 0; c < k; ++c) d += (q[c] - start[c]) * (q[c] - start[c]);
      plan.radius = std::max(plan.radius, std::sqrt(d));
    });
    plan.radius *= 1.1;  // the sample may miss the attractor's far tips
    plan.cut = cut;
    int needed = fallback_depth;
    if (largest < 1.0 && largest > 0.0 && plan.radius > cut)
      needed = std::max(needed, static_cast<int>(std::ceil(std::log(cut / plan.radius) / std::log(largest))));
    plan.max_depth = std::min(std::max(needed, 1), 64);
  }
  const std::uint64_t n = ifs.size();
  plan.prefix = 0;
  plan.jobs = 1;
  if (n > 1) {
    // At least 64 jobs (load balance); at most ~2^20 leaves per fixed-depth job (memory).
    double below = std::pow(static_cast<double>(n), plan.max_depth);
    while (plan.prefix < plan.max_depth && plan.jobs * n <= (1u << 24) &&
           (plan.jobs < 64 || below > (1u << 20))) {
      ++plan.prefix;
      plan.jobs *= n;
      below /= static_cast<double>(n);
    }
  }
  return plan;
}

void walk_job(const Ifs& ifs, const RecursionPlan& plan, const Point& start, std::uint64_t job,
              const std::function<void(const Point&, double, const std::uint32_t*, int)>& leaf) {
  Walker walker{ifs, plan, leaf, {}};
  const std::uint64_t n = ifs.size();
  // Digits of the job index, most significant first.
  std::uint64_t rest = job;
  for (int level = plan.prefix - 1; level >= 0; --level) {
    walker.address[level] = static_cast<std::uint32_t>(rest % n);
    rest /= n;
  }
  Point p = start, q;
  double mass = 1.0, bound = 1.0;
  if (plan.prefix == 0) {
    walker.recurse(p, mass, bound, 0);
    return;
  }
  for (int level = 0; level < plan.prefix; ++level) {
    const std::uint32_t i = walker.address[level];
    ifs.map(i).apply(p.data(), q.data());
    p = q;
    mass *= ifs.probabilities()[i];
    bound *= plan.bound[i];
    if (walker.stop(level + 1, bound)) {
      for (int later = level + 1; later < plan.prefix; ++later)
        if (walker.address[later] != 0) return;  // another job reports this leaf
      leaf(p, mass, walker.address, level + 1);
      return;
    }
  }
  walker.recurse(p, mass, bound, plan.prefix);
}

}  // namespace ifsforge
