#pragma once
/// @file Separable CMA-ES (Ros & Hansen 2008: diagonal covariance, linear cost per sample), the
/// search of the automatic fitting. Samples are drawn serially from one seeded stream and
/// evaluated in parallel, so the result does not depend on the thread count.
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

namespace ifsforge {

struct CmaOptions {
  int population = 0;        ///< lambda; 0: 4 + 3 ln n
  int max_generations = 200;
  double tolerance = 1e-7;   ///< stop when 20 generations' best values lie within this
  /// No value lies below it (a fit's 1 - IoU, a distance): a best value there cannot be replaced,
  /// as only a smaller one replaces it, so the search stops with the result it would end with.
  double floor = -std::numeric_limits<double>::infinity();
  /// Asked of each new best: true when it is as good as the caller can want (a fit whose best,
  /// snapped onto the target's lattice, draws the target exactly); the search stops with it.
  std::function<bool(const std::vector<double>&)> reached;
  std::uint64_t seed = 0;
  int threads = 0;
};

struct CmaResult {
  std::vector<double> best;
  double value = 0;
  std::uint64_t evaluations = 0;
};

/// @brief Minimises f(x, worker) from `start` with initial step `sigma` per coordinate
/// (worker identifies per-thread scratch). `stop()` is asked between generations.
CmaResult minimize_cma(const std::function<double(const std::vector<double>&, int worker)>& f,
                       const std::vector<double>& start, const std::vector<double>& sigma, const CmaOptions& options,
                       const std::function<bool()>& stop = nullptr);

}  // namespace ifsforge
