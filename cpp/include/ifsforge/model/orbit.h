#pragma once
/// @file The one walker of random iteration (seed 5.1.1): which map follows which, and a point
/// that follows them. Every random-iteration path (chaos, colour stealing, the random-iteration
/// volume, the preview cloud, the samplers and the fits) draws its maps from a MapChain, so
/// none of them can drop a recurrent system's transitions.
#include <cstdint>
#include <vector>

#include "ifsforge/core/random.h"
#include "ifsforge/model/ifs.h"
#include "ifsforge/model/map_sampler.h"

namespace ifsforge {

/// @brief The sequence of maps of random iteration. An ordinary IFS draws each map on its own
/// with the probabilities p_i; a recurrent IFS (3.3.1) draws it from row i of its transition
/// matrix, i being the map applied before, so the orbit stays on the union of the pieces A_j
/// and never visits w_j(A_i) when P(i, j) = 0. A super IFS (3.3.5) draws from Eq. 38's
/// P_n p_nm: its orbit covers the union of the members, which holds every member's attractor
/// and every superfractal (the superfractal renderer, dia-s, makes the members' choices).
class MapChain {
 public:
  explicit MapChain(const Ifs& ifs);
  /// @brief Independent draws with `probabilities` (an ordinary IFS).
  explicit MapChain(const std::vector<double>& probabilities);

  /// @brief Whether the next map depends on the previous one (a recurrent system).
  bool follows_transitions() const { return recurrent_; }
  std::size_t size() const { return rows_.front().size(); }

  /// @brief The state before the first step. Recurrent: a map drawn from the chain's
  /// stationary distribution (one random word): the map taken to have placed the start point.
  /// Ordinary: 0, and no word is drawn, so an ordinary system's stream is what a plain
  /// MapSampler of its probabilities draws.
  std::uint32_t start(Rng& rng) const { return recurrent_ ? first_(rng.next()) : 0; }
  /// @brief The map that follows `previous`, for one 64-bit random word.
  std::uint32_t next(std::uint32_t previous, std::uint64_t random) const {
    return row(previous)(random);
  }
  /// @brief The sampler that draws the map after `previous`.
  const MapSampler& row(std::uint32_t previous) const { return rows_[recurrent_ ? previous : 0]; }

 private:
  bool recurrent_ = false;
  MapSampler first_;
  std::vector<MapSampler> rows_;  ///< one per map (recurrent), else one
};

/// @brief A point walking the attractor: each step draws the next map from the chain and
/// applies it with Ifs::apply (polar maps too). For loops that are not hot; the hot kernels
/// draw from a MapChain and apply their own unrolled maps.
class Orbit {
 public:
  /// @brief Stream (seed, stream); the point starts at `start` (default Ifs::start_point()).
  Orbit(const Ifs& ifs, const MapChain& chain, std::uint64_t seed, std::uint64_t stream);
  Orbit(const Ifs& ifs, const MapChain& chain, std::uint64_t seed, std::uint64_t stream, const Point& start);
  /// @brief One step: returns the map applied.
  std::uint32_t step() {
    map_ = chain_.next(map_, rng_.next());
    point_ = ifs_.apply(map_, point_);
    return map_;
  }
  /// @brief `count` steps, plotting nothing (min_no_of_iterations of 5.1.1).
  void skip(std::uint64_t count) {
    for (std::uint64_t i = 0; i < count; ++i) step();
  }
  const Point& point() const { return point_; }
  /// @brief The map applied last (the chain's state).
  std::uint32_t map() const { return map_; }
  /// @brief DivergentSystemError naming the system when the point is no longer finite.
  void require_finite() const;

 private:
  const Ifs& ifs_;
  const MapChain& chain_;
  Rng rng_;
  std::uint32_t map_;
  Point point_;
};

}  // namespace ifsforge
