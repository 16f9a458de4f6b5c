#pragma once
/// @file Normalising map probabilities (seed Definitions 6 and 10: p_1 + ... + p_N = 1) and
/// transition rows as a fixed point.
#include <cstddef>
#include <vector>

namespace ifsforge {

/// @brief Divides `probabilities` (>= 0, summing to `total` > 0) by their sum, unless they
/// already sum to 1 up to the rounding of a sum: normalising is then a fixed point, so a system
/// written at round-trip precision and read back keeps the same probabilities (and draws the
/// same maps).
void normalise_probabilities(double* probabilities, std::size_t count, double total);

inline void normalise_probabilities(std::vector<double>& probabilities, double total) {
  normalise_probabilities(probabilities.data(), probabilities.size(), total);
}

}  // namespace ifsforge
