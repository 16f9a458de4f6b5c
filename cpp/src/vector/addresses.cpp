#include "ifsforge/vector/addresses.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

#include "address_tree.h"
#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/render/parameters.h"
#include "ifsforge/render/string_rewriting.h"

namespace ifsforge {
namespace detail {

TreeShape plan_tree(const Ifs& ifs, int depth, double min_probability) {
  if (depth < 1 || depth > kMaxAddressDepth)
    throw InputError("the recursion depth must be 1.." + std::to_string(kMaxAddressDepth) + ", got " +
                     std::to_string(depth));
  if (!(min_probability >= 0.0 && min_probability < 1.0))
    throw InputError("the pruning probability pv must be in [0, 1)");
  if (ifs.size() >= kNoMap) throw InputError("addresses hold at most 65534 maps");
  if (ifs.recurrent())
    throw InputError("system '" + ifs.name() + "' is a recurrent IFS: its address tree follows transitions, "
                     "which the vector and address algorithms do not");
  if (!ifs.condensation().empty())
    throw InputError("system '" + ifs.name() + "' has a condensation set, which the vector and address algorithms "
                     "do not place");
  TreeShape shape;
  // Fixed depth: >= 64 jobs of <= ~2^20 leaves. Pruned trees end early where probabilities are
  // small, so they only need enough jobs to balance (the automatic-depth split).
  shape.plan = min_probability > 0.0 ? plan_recursion(ifs, 0, depth) : plan_recursion(ifs, depth, depth);
  shape.depth = depth;
  shape.min_probability = min_probability;
  for (int level = shape.plan.prefix; level < depth; ++level) shape.leaves_per_job *= ifs.size();
  return shape;
}

double leaves_at_least(const Ifs& ifs, const TreeShape& shape) {
  const double n = static_cast<double>(ifs.size());
  if (!(shape.min_probability > 0.0) || ifs.size() < 2) return std::pow(n, shape.depth);
  constexpr int kSteps = 2048;  // steps of -log p up to -log pv
  const double step = -std::log(shape.min_probability) / kSteps;
  // Maps per step, rounded up (each node's probability under-estimated: a lower bound); maps
  // of probability 0 (or below pv) are never internal.
  std::vector<double> maps(kSteps + 1, 0.0);
  for (double p : ifs.probabilities()) {
    const double s = std::ceil(-std::log(p) / step);
    if (p >= shape.min_probability && s <= kSteps) maps[static_cast<int>(s)] += 1.0;
  }
  std::vector<int> used;
  for (int k = 0; k <= kSteps; ++k)
    if (maps[k] > 0.0) used.push_back(k);
  std::vector<double> level(kSteps + 1, 0.0), next(kSteps + 1);
  level[0] = 1.0;  // the root
  double internal = 0.0;
  for (int d = 0; d < shape.depth; ++d) {
    std::fill(next.begin(), next.end(), 0.0);
    double here = 0.0;
    for (int b = 0; b <= kSteps; ++b) {
      if (level[b] == 0.0) continue;
      here += level[b];
      for (int k : used)
        if (b + k <= kSteps) next[b + k] += level[b] * maps[k];
    }
    internal += here;
    if (here == 0.0) break;
    level.swap(next);
  }
  return (n - 1.0) * internal + 1.0;
}

namespace {

/// Refuses `leaves` (`at_least`: counted so far) of `shape` above 10^12 or the memory budget.
void check_leaves(double leaves, bool at_least, const TreeShape& shape, const LeafCost& cost) {
  char count[64];
  std::snprintf(count, sizeof count, "%s%.4g ", at_least ? "at least " : "", leaves);
  char tree[160];
  std::snprintf(tree, sizeof tree, " (depth %d, minimum probability %g: choose a smaller depth or a larger minimum "
                "probability, --depth and --min-probability)", shape.depth, shape.min_probability);
  const std::string what = count + cost.what + tree;
  if (leaves > static_cast<double>(kMaxIterations)) throw InputError(what + " are more than 10^12: work for hours");
  if (cost.bytes > 0.0) check_memory(leaves * cost.bytes, what);
}

}  // namespace

std::vector<std::uint64_t> job_offsets(const Ifs& ifs, const TreeShape& shape, int threads, const LeafCost& cost) {
  const std::uint64_t jobs = shape.plan.jobs;
  std::vector<std::uint64_t> offsets(jobs + 1, 0);
  if (shape.min_probability <= 0.0) {
    for (std::uint64_t j = 0; j < jobs; ++j) offsets[j + 1] = offsets[j] + shape.leaves_per_job;
    check_leaves(static_cast<double>(offsets.back()), false, shape, cost);
    return offsets;
  }
  check_leaves(leaves_at_least(ifs, shape), true, shape, cost);
  // The bound may lie under the limit and the tree above it: the count stops as soon as the
  // leaves met pass it.
  double limit = static_cast<double>(kMaxIterations);
  if (cost.bytes > 0.0) limit = std::min(limit, static_cast<double>(memory_budget()) / cost.bytes);
  std::atomic<std::uint64_t> met{0};
  constexpr std::uint64_t kFlush = 1u << 16;
  std::vector<std::uint64_t> counts(jobs, 0);
  parallel_jobs(jobs, threads, [&](std::size_t job, int) {
    std::uint64_t count = 0;
    walk_job(ifs, shape.plan, job, ProbabilityStop{shape.min_probability}, [&](const RecursionNode&) {
      if (++count % kFlush == 0 && static_cast<double>(met += kFlush) > limit)
        check_leaves(static_cast<double>(met.load()), true, shape, cost);
    });
    counts[job] = count;
    met += count % kFlush;
  });
  for (std::uint64_t j = 0; j < jobs; ++j) offsets[j + 1] = offsets[j] + counts[j];
  check_leaves(static_cast<double>(offsets.back()), false, shape, cost);
  return offsets;
}

}  // namespace detail

std::string address_string(const std::uint16_t* address, int length) {
  std::string out;
  for (int i = 0; i < length; ++i) {
    if (i) out += '.';
    out += std::to_string(address[i]);
  }
  return out;
}

std::string AddressTable::to_string(std::size_t i) const { return address_string(address(i), lengths[i]); }

Point apply_address(const Ifs& ifs, const std::uint16_t* address, int length, const Point& point) {
  Point p = point, q;
  for (int i = length - 1; i >= 0; --i) {  // the innermost map first
    if (address[i] >= ifs.size())
      throw InputError("address digit " + std::to_string(address[i]) + " names no map (the system has " +
                       std::to_string(ifs.size()) + ")");
    ifs.map(address[i]).apply(p.data(), q.data());
    p = q;
  }
  return p;
}

std::uint64_t count_leaves(const Ifs& ifs, int depth, double min_probability) {
  const detail::TreeShape shape = detail::plan_tree(ifs, depth, min_probability);
  return detail::job_offsets(ifs, shape, 0, {0.0, "leaves"}).back();
}

std::vector<std::string> string_rewriting(const Ifs& ifs, int depth, AddressSpelling spelling) {
  const std::uint64_t leaves = count_leaves(ifs, depth, 0.0);
  check_memory(leaves * (2.0 * sizeof(std::string) + 4.0 * depth + 16.0), std::to_string(leaves) + " address strings");
  const bool seed = spelling == AddressSpelling::Seed;
  std::vector<std::string> maps;  // 0-based digits joined by '.', or the seed's w1 ... wN
  for (std::size_t k = 0; k < ifs.size(); ++k) maps.push_back(seed ? "w" + std::to_string(k + 1) : std::to_string(k));
  return rewrite_map_strings(maps, seed ? "" : ".", depth);
}

AddressLeaves tesseral_synecdoche(const Ifs& ifs, int depth, double min_probability,
                                  const std::vector<double>& start, int threads,
                                  const ProgressCallback& progress) {
  ifs.require_affine("tesseral synecdoche");
  const detail::TreeShape shape = detail::plan_tree(ifs, depth, min_probability);
  Point q0 = ifs.start_point();
  if (!start.empty()) {
    if (static_cast<int>(start.size()) != ifs.dim())
      throw InputError("the start point needs " + std::to_string(ifs.dim()) + " coordinates");
    for (int c = 0; c < ifs.dim(); ++c) q0[c] = start[c];
  }
  const int dim = ifs.dim();
  const std::vector<std::uint64_t> offsets =
      detail::job_offsets(ifs, shape, threads, {2.0 * depth + 1.0 + 8.0 + 8.0 * dim, "TSA leaves"});
  const std::uint64_t total = offsets.back();

  AddressLeaves out;
  out.dim = dim;
  AddressTable& t = out.addresses;
  t.depth = depth;
  t.digits.assign(total * depth, kNoMap);
  t.lengths.assign(total, 0);
  t.probabilities.assign(total, 0.0);
  out.points.assign(total * dim, 0.0);
  parallel_jobs(shape.plan.jobs, threads, [&](std::size_t job, int) {
    std::uint64_t slot = offsets[job];
    walk_job(ifs, shape.plan, job, detail::ProbabilityStop{min_probability}, [&](const RecursionNode& node) {
      std::copy(node.address, node.address + node.length, t.digits.begin() + slot * depth);
      t.lengths[slot] = static_cast<std::uint8_t>(node.length);
      t.probabilities[slot] = node.mass;
      node.map.apply(q0.data(), out.points.data() + slot * dim);
      ++slot;
    });
  }, progress);
  return out;
}

}  // namespace ifsforge
