#pragma once
// The address tree of the TSA (5.7) and of vector recursive rendering (5.8.2), on top of the
// recursive renderers' walk (render/recursion.h): leaves at a fixed depth or where the address
// probability drops below pv, address-prefix jobs, and where each job's leaves go in the
// output so that jobs write straight into their slots. Internal to src/vector.
#include <cstdint>
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

/// @brief Leaves of each job (counted in parallel when pruning makes them unknown) as exclusive
/// prefix sums: job j writes leaves [offsets[j], offsets[j + 1]).
std::vector<std::uint64_t> job_offsets(const Ifs& ifs, const TreeShape& shape, int threads);

}  // namespace ifsforge::detail
