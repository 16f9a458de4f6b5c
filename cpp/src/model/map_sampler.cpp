#include "ifsforge/model/map_sampler.h"

#include <cmath>

namespace ifsforge {

MapSampler::MapSampler(const std::vector<double>& probabilities)
    : size_(probabilities.size()), threshold_(size_), alias_(size_) {
  // Vose's stable variant of the alias method.
  double total = 0.0;
  for (double p : probabilities) total += p;
  std::vector<double> scaled(size_);
  std::vector<std::uint32_t> small, large;
  for (std::size_t i = 0; i < size_; ++i) {
    scaled[i] = probabilities[i] / total * static_cast<double>(size_);
    (scaled[i] < 1.0 ? small : large).push_back(static_cast<std::uint32_t>(i));
  }
  auto set = [&](std::uint32_t i, double keep, std::uint32_t other) {
    const double t = std::ldexp(keep, 32);
    threshold_[i] = t >= 4294967295.0 ? 0xFFFFFFFFu : static_cast<std::uint32_t>(t);
    alias_[i] = other;
  };
  while (!small.empty() && !large.empty()) {
    const std::uint32_t s = small.back(), l = large.back();
    small.pop_back();
    set(s, scaled[s], l);
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  for (std::uint32_t l : large) set(l, 1.0, l);
  for (std::uint32_t s : small) set(s, 1.0, s);  // round-off leftovers
}

}  // namespace ifsforge
