#include "ifsforge/model/orbit.h"

#include <cmath>

#include "ifsforge/core/error.h"

namespace ifsforge {

MapChain::MapChain(const Ifs& ifs) : recurrent_(ifs.recurrent()), first_(ifs.probabilities()) {
  if (!recurrent_) {
    rows_.push_back(first_);
    return;
  }
  // The probabilities of a recurrent system are its chain's stationary distribution.
  for (std::size_t i = 0; i < ifs.size(); ++i) rows_.emplace_back(ifs.transitions().row(i));
}

MapChain::MapChain(const std::vector<double>& probabilities) : first_(probabilities), rows_{first_} {}

Orbit::Orbit(const Ifs& ifs, const MapChain& chain, std::uint64_t seed, std::uint64_t stream)
    : Orbit(ifs, chain, seed, stream, ifs.start_point()) {}

Orbit::Orbit(const Ifs& ifs, const MapChain& chain, std::uint64_t seed, std::uint64_t stream, const Point& start)
    : ifs_(ifs), chain_(chain), rng_(seed, stream), point_(start) {
  map_ = chain_.start(rng_);
}

void Orbit::require_finite() const {
  for (int c = 0; c < ifs_.dim(); ++c)
    if (!std::isfinite(point_[c]))
      throw DivergentSystemError("system '" + ifs_.name() + "' escapes to infinity under iteration");
}

}  // namespace ifsforge
