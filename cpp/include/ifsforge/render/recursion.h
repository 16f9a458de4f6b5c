#pragma once
/// @file The address tree shared by the recursive renderers (seed 5.6-5.8): nodes, the plan of
/// how deep to go, and the split into address-prefix jobs.
///
/// A node at address (a1, ..., ak) stands for the sub-attractor w_a1 o w_a2 o ... o w_ak (A):
/// the FIRST map of the address is the outermost. Carrying the composed map M = w_a1 o ... o w_ak
/// makes every subtree a small piece of the attractor, M(A), inside the box M(B) where B bounds A:
/// a renderer can stop as soon as M(B) fits in one pixel or voxel, and the leaf mass
/// p_a1 ... p_ak is exactly the invariant measure of that piece.
/// Jobs are address prefixes of fixed length: the seam along which work splits across threads
/// (and, later, machines); results merged in job order do not depend on the thread count.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "ifsforge/core/error.h"
#include "ifsforge/core/parallel.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/render/frame.h"

namespace ifsforge {

struct RecursionPlan {
  int max_depth = 1;           ///< no node deeper than this
  int prefix = 0;              ///< address length of one job
  std::uint64_t jobs = 1;      ///< N^prefix
  std::vector<double> center;  ///< the box B bounding the attractor (all channels): centre
  std::vector<double> half;    ///< and half-extent, with a safety margin
  /// Jobs cut by their work (balance_jobs): addresses of unequal length, in address order.
  /// Empty: job k is the length-`prefix` address whose base-N digits are k.
  std::vector<std::vector<std::uint32_t>> addresses;
};

/// @brief A node of the address tree.
struct RecursionNode {
  const AffineMap& map;             ///< w_a1 o ... o w_ak
  double mass;                      ///< p_a1 ... p_ak
  const std::uint32_t* address;     ///< a1 ... ak (0-based map indices)
  int length;                       ///< k
};

/// Images grow a sampled attractor box by this share of its extent per side (a sample may miss
/// the far tips).
constexpr double kPieceBoxMargin = 0.02;

/// @brief The box B every piece is an image of, as `center` and `half` (all channels): the
/// smallest box with AABB(w_i(B)) inside B when the system has one (exact for axis-aligned
/// maps: a grid-aligned fractal's pieces then lie on cell faces, and nest), else `bounds`
/// grown by `margin` of its extent per side, for the tips a sample may miss. When only the
/// spatial rows have one (channels that do not feed the position), those rows are exact.
/// Unless `any_invariant`, an invariant box wider than the grown bounds is not taken.
void piece_box(const Ifs& ifs, const Bounds& bounds, double margin, bool any_invariant, std::vector<double>& center,
               std::vector<double>& half);

/// @brief InputError naming `depth` when a fixed depth gives `maps`^depth leaves, more than
/// 10^12 (the limit on chaos game points, kMaxIterations): work that would run for hours.
void check_leaf_count(std::size_t maps, int depth);

/// @brief A plan for `ifs`. depth > 0: exactly that depth (the seed's PRR: N^depth leaves;
/// check_leaf_count).
/// depth == 0: `auto_depth`, which should be deep enough for the renderer's stop test to end
/// every branch; pass default_depth() (Eq. 59) or more. Jobs: at least 64 (load balance), with
/// at most ~2^20 leaves each at fixed depth (memory of per-job results). The box's sample walks
/// on up to `threads` cores (Ifs::attractor_bounds): the same plan.
RecursionPlan plan_recursion(const Ifs& ifs, int depth, int auto_depth, int threads = 1);

/// @brief The address (prefix) that job `job` of `plan` walks below.
std::vector<std::uint32_t> job_address(const Ifs& ifs, const RecursionPlan& plan, std::uint64_t job);

/// @brief Cuts the tree into jobs by their work, `weight(M)` for the piece M(B) (its area in
/// pixels, say): the heaviest piece is split into its N children until none holds more than
/// 1/256 of the root's weight (at least 64 jobs, at most 2^14). A uniform prefix cannot balance
/// a system with one dominant map: one prefix of the fern (111) holds over a third of its
/// pixels, and one thread would walk it alone while the others wait. The cut depends on the system and the
/// weight only, never on the thread count.
void balance_jobs(const Ifs& ifs, RecursionPlan& plan, const std::function<double(const AffineMap&)>& weight);

/// @brief The depth at which the least contractive branch shrinks the attractor's box below
/// `size` (in the units of the space), plus `extra` levels, capped at 64; Eq. 59's
/// `fallback` when some map does not contract.
int depth_for_size(const Ifs& ifs, const RecursionPlan& plan, double size, int extra, int fallback);

/// @brief The centre of B as a point: a leaf plots at its image M(centre), the centre of its
/// piece's box, so a grid-aligned piece lands inside its own cell, never on a boundary.
inline Point box_center(const RecursionPlan& plan) {
  Point c{};
  for (std::size_t k = 0; k < plan.center.size(); ++k) c[k] = plan.center[k];
  return c;
}

/// @brief Axis-aligned box of M(B) on rows [0, rows): centre and half-extent.
inline void image_box(const AffineMap& m, const RecursionPlan& plan, int rows, double* center, double* half) {
  const int n = m.dim();
  for (int r = 0; r < rows; ++r) {
    double c = m.b(r), h = 0.0;
    for (int k = 0; k < n; ++k) {
      c += m.a(r, k) * plan.center[k];
      h += (m.a(r, k) < 0 ? -m.a(r, k) : m.a(r, k)) * plan.half[k];
    }
    center[r] = c;
    half[r] = h;
  }
}

/// @brief Pixel-space box [lo, hi) per image axis of a node's piece M(B): the box of B under
/// the piece's map straight to pixels (what the point recursive walk composes level by level).
inline void piece_pixel_box(const Frame& frame, const RecursionPlan& plan, const AffineMap& m, double* lo, double* hi) {
  PixelTransform t;
  frame.pixel_transform(m, t);
  t.box(plan.center.data(), plan.half.data(), lo, hi);
}

namespace detail {

template <typename Stop, typename Leaf>
struct Walker {
  Walker(const Ifs& system, const RecursionPlan& p, Stop& s, Leaf& l) : ifs(system), plan(p), stop(s), leaf(l) {
    // Composed maps down to the deepest level reached so far: a job that ends near the root
    // builds few (a map is 0.5 KB; a long prefix of jobs is walked by every job).
    maps.reserve(static_cast<std::size_t>(plan.max_depth) + 2);
    maps.emplace_back(ifs.dim());
  }
  const Ifs& ifs;
  const RecursionPlan& plan;
  Stop& stop;
  Leaf& leaf;
  std::uint32_t address[64];
  std::uint32_t visits = 0;
  std::vector<AffineMap> maps;  // maps[k]: the composition of the first k maps of `address`
  // The walk's own copy of the probabilities, read at every node: the system's array may sit
  // beside memory another thread is writing (false sharing).
  const std::vector<double> probability = ifs.probabilities();

  /// Sets maps[length + 1] = maps[length] o w_i (reserved: references to it stay valid).
  void descend(int length, std::uint32_t i) {
    if (maps.size() < static_cast<std::size_t>(length) + 2) maps.emplace_back();
    maps[length].compose_into(ifs.map(i), maps[length + 1]);
  }

  void recurse(int length, double mass) {
    for (std::uint32_t i = 0; i < ifs.size(); ++i) {
      address[length] = i;
      descend(length, i);
      // A job may hold most of a render (the fern's densest prefix): Ctrl-C reaches it here.
      if ((++visits & 0xfff) == 0 && stop_requested()) throw Cancelled();
      const RecursionNode node{maps[length + 1], mass * probability[i], address, length + 1};
      if (node.length >= plan.max_depth || stop(node))
        leaf(node);
      else
        recurse(length + 1, node.mass);
    }
  }
};

}  // namespace detail

/// @brief Visits every leaf below job `job` (digits of the job index, most significant first,
/// are the address prefix). A node ends as a leaf at plan.max_depth or when stop(node) is true;
/// a node that stops inside the prefix is reported by the one job whose remaining prefix digits
/// are all 0, so every leaf is visited exactly once over all jobs.
template <typename Stop, typename Leaf>
void walk_job(const Ifs& ifs, const RecursionPlan& plan, std::uint64_t job, Stop&& stop, Leaf&& leaf) {
  detail::Walker<Stop, Leaf> w(ifs, plan, stop, leaf);
  const std::vector<std::uint32_t> prefix = job_address(ifs, plan, job);
  const int length = static_cast<int>(prefix.size());
  std::copy(prefix.begin(), prefix.end(), w.address);
  double mass = 1.0;
  for (int level = 0; level < length; ++level) {
    const std::uint32_t i = w.address[level];
    w.descend(level, i);
    mass *= ifs.probabilities()[i];
    const RecursionNode node{w.maps[level + 1], mass, w.address, level + 1};
    if (level + 1 >= plan.max_depth || stop(node)) {
      // Every split node has all N children among the jobs (either cut): the one whose later
      // digits are all 0 reports this node.
      for (int later = level + 1; later < length; ++later)
        if (w.address[later] != 0) return;
      leaf(node);
      return;
    }
  }
  if (length == 0 && plan.max_depth == 0) return;
  w.recurse(length, mass);
}

}  // namespace ifsforge
