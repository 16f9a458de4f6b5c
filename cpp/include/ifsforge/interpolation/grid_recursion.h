#pragma once
/// @file Exact evaluation of a fractal interpolation function on a uniform sample grid.
///
/// With N equally spaced nodes on [0, 1] the maps of Eq. 91 send x to (x + i) / N. For M
/// equally spaced samples t / (M - 1), every sample in the i-th interval has its preimage
/// s = N t - i (M - 1) on the same grid, so the fixed-point equation of the graph,
/// f(t) = a21_i v(s) + b2_i + a22_i f(s), links grid values to grid values only. The
/// dependencies form a functional graph (each sample has one successor) whose roots are the
/// data nodes and whose cycles close the equation on themselves; solving each cycle in closed
/// form and unwinding the chains gives every sample exactly, in O(M), for any M.
/// The plan depends only on (N, M): the same plan serves any data and any a22.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace ifsforge {

class GridRecursion {
 public:
  enum class Kind : std::uint8_t {
    Node,   ///< sample `target` is data node `index`
    Step,   ///< f[target] = a21_map v(source) + b2_map + a22_map f[source]
    Cycle,  ///< f[target] from the cycle terms [index, index + count) in closed form
  };
  struct Op {
    std::uint32_t target;
    std::uint32_t source;  ///< Step: the preimage sample
    std::uint32_t map;     ///< Step: the map (0-based: the seed's i - 1)
    std::uint32_t index;   ///< Node: the data node; Cycle: the first term
    std::uint32_t count;   ///< Cycle: the cycle length
    Kind kind;
  };
  /// One link of a cycle q_0 -> q_1 -> ... -> q_0: the map used at q_k and q_{k+1}.
  struct CycleTerm {
    std::uint32_t source;
    std::uint32_t map;
  };

  /// @brief The plan for `intervals` = N >= 2 equally spaced intervals and `samples` = M >= 2
  /// equally spaced samples over the same range. InputError otherwise (or M >= 2^32).
  GridRecursion(std::size_t intervals, std::size_t samples);

  std::size_t intervals() const { return intervals_; }
  std::size_t samples() const { return samples_; }
  /// @brief Every sample appears exactly once as a target, after the samples it needs.
  const std::vector<Op>& ops() const { return ops_; }
  const std::vector<CycleTerm>& cycle_terms() const { return terms_; }
  /// @brief The normalised position t / (M - 1) of sample t.
  double position(std::uint32_t t) const { return static_cast<double>(t) / static_cast<double>(samples_ - 1); }

  /// @brief Runs the plan on scalars. `values` holds the N + 1 data values, `a22` the N
  /// vertical scaling factors; writes M values to `out`. The maps are Eq. 94 on [0, 1].
  void evaluate(const double* values, const double* a22, double* out) const;

 private:
  std::size_t intervals_, samples_;
  std::vector<Op> ops_;
  std::vector<CycleTerm> terms_;
};

}  // namespace ifsforge
