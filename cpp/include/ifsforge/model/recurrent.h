#pragma once
/// @file Recurrent IFS (seed 3.3.1 and 5.12): which map may follow which.
#include <cstddef>
#include <vector>

#include "ifsforge/model/affine_map.h"

namespace ifsforge {

class Ifs;

/// @brief An N x N row-stochastic matrix: (i, j) is the probability that map j follows map i
/// (Barnsley's recurrent IFS). The attractor is the union of the pieces
/// A_j = w_j(union of A_i over the i with P(i, j) > 0). Empty for an ordinary IFS.
class TransitionMatrix {
 public:
  TransitionMatrix() = default;
  /// @brief Normalises the rows. InputError names the entry or row that is wrong (negative or
  /// non-finite entries, a row summing to 0) or says the chain is reducible: its graph must be
  /// strongly connected so that the chain has exactly one stationary distribution.
  TransitionMatrix(std::size_t size, std::vector<double> row_major);
  /// @brief Every row equal to `probabilities`: independent choices, an ordinary IFS.
  static TransitionMatrix independent(const std::vector<double>& probabilities);

  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }
  double operator()(std::size_t i, std::size_t j) const { return p_[i * size_ + j]; }
  const std::vector<double>& values() const { return p_; }
  std::vector<double> row(std::size_t i) const;
  /// @brief m with m P = m and sum m = 1: how often each map is applied in the long run.
  std::vector<double> stationary() const;
  /// @brief Eq. 73's reversed chain r(j, i) = m_i P(i, j) / m_j: the share of the measure on
  /// piece A_j that w_j brings from piece A_i (row-stochastic).
  TransitionMatrix reversed() const;

 private:
  std::size_t size_ = 0;
  std::vector<double> p_;
};

/// @brief The transitions in effect: the system's own matrix, or, for an ordinary IFS, every
/// row equal to its probabilities.
TransitionMatrix effective_transitions(const Ifs& ifs);

/// @brief One point of each piece A_j, from a seeded walk of the chain (the point just after
/// w_j was applied lies on A_j).
std::vector<Point> piece_points(const Ifs& ifs);

}  // namespace ifsforge
