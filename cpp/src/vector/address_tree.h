#pragma once
// The address tree of the TSA (5.7) and of vector recursive rendering (5.8.2), on top of the
// recursive renderers' walk (render/recursion.h): leaves at a fixed depth or where the address
// probability drops below pv, address-prefix jobs, and where each job's leaves go in the
// output so that jobs write straight into their slots. Internal to src/vector.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/model/ifs.h"
#include "ifsforge/render/recursion.h"
#include "ifsforge/vector/addresses.h"

namespace ifsforge::detail {

struct TreeShape {
  RecursionPlan plan;
  int depth = 0;                 ///< leaves no deeper than this
  double min_probability = 0.0;  ///< pv
  /// Leaves per job when nothing is pruned: N^(depth - prefix).
  std::uint64_t leaves_per_job = 1;
};

/// The TSA's pruning test: a node less probable than pv ends its branch.
struct ProbabilityStop {
  double min_probability;
  bool operator()(const RecursionNode& node) const { return node.mass < min_probability; }
};

/// @brief Validates depth (1..kMaxAddressDepth) and pv ([0, 1)), refuses 65535 maps or more,
/// more than 10^12 leaves (check_leaf_count), and recurrent systems or condensation sets (every map may follow every
/// other in the address tree), and plans the jobs.
TreeShape plan_tree(const Ifs& ifs, int depth, double min_probability);

/// @brief A lower bound on the leaves of `shape`, found without walking it (exact without
/// pruning). With pruning, a node whose probability is at least pv has all N children, so the
/// leaves are (N - 1) I + 1 for the I such nodes above the depth; I is counted by -log
/// probability on a grid of steps, each map's step rounded up, in depth x steps x
/// distinct-steps work.
double leaves_at_least(const Ifs& ifs, const TreeShape& shape);

/// What each leaf will cost, for the refusals of job_offsets().
struct LeafCost {
  double bytes = 0.0;  ///< memory per leaf (0: counted only)
  std::string what;    ///< the leaves' name in messages ("instances", "TSA leaves")
};

/// @brief Leaves of each job (counted in parallel when pruning makes them unknown) as exclusive
/// prefix sums: job j writes leaves [offsets[j], offsets[j + 1]). Refuses before walking when
/// leaves_at_least() proves more than 10^12 leaves or more than the memory budget at `cost`, and
/// stops counting as soon as the leaves met exceed either (MemoryBudgetError or InputError naming
/// the depth and pv).
std::vector<std::uint64_t> job_offsets(const Ifs& ifs, const TreeShape& shape, int threads, const LeafCost& cost);

}  // namespace ifsforge::detail
