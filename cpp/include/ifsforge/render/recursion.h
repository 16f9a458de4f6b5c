#pragma once
/// @file The address-tree walk shared by the recursive renderers: which contraction bound to
/// trust, how far to recurse, and the split into address-prefix jobs.
#include <cstdint>
#include <functional>
#include <vector>

#include "ifsforge/model/ifs.h"

namespace ifsforge {

struct RecursionPlan {
  int max_depth = 0;      ///< no leaf deeper than this
  double cut = 0.0;       ///< stop when bound * radius <= cut (0: fixed depth)
  double radius = 0.0;    ///< max distance from the start point to the attractor
  std::vector<double> bound;  ///< per-map contraction bound used for the cut
  int prefix = 0;         ///< address length of one job
  std::uint64_t jobs = 1; ///< N^prefix
};

/// @brief A plan for `ifs`: fixed `depth` if > 0, else a cut at `cut` (in the units of the
/// space; spatial when the spatial rows do not read the other channels) with depth capped by
/// `depth_cap`.
RecursionPlan plan_recursion(const Ifs& ifs, int depth, double cut, int depth_cap);

/// @brief Walks every leaf below job `job` (an address prefix, most significant map first),
/// calling leaf(point, mass, address, length). A branch cut above the prefix is reported only
/// by the job whose remaining prefix digits are all 0, so each leaf is reported once.
void walk_job(const Ifs& ifs, const RecursionPlan& plan, const Point& start, std::uint64_t job,
              const std::function<void(const Point&, double, const std::uint32_t*, int)>& leaf);

}  // namespace ifsforge
