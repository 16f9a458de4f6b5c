#pragma once
// The rate control's search over λ (encoder.cpp): the bracket of log λ that holds the largest
// file within the target, narrowed two values of λ at a time.
#include <array>
#include <cstddef>

#include "ifsforge/core/image.h"

namespace ifsforge {

/// @brief log λ where the search starts: from the bits per sample the target leaves (a line
/// through the camera and astronaut photographs' λ at 5:1 to 100:1; only a start, the search
/// finds the true one).
double lambda_guess(const Image& image, std::size_t target);

/// @brief A bracket [lo, hi] of log λ: lo gives a file above the target (or is the lowest λ, not
/// yet tried), hi one within it (or is the highest λ). The file's log size is close to linear in
/// log λ, so each round interpolates where it meets the target (extrapolates while one side is
/// untried) and tries two values a little either side of it: a round narrows the bracket about
/// tenfold where a trisection narrows it threefold. A round that fails to halve the bracket is
/// followed by a trisection, so the search ends however the size behaves.
class LambdaBracket {
 public:
  static constexpr double kLowest = -6.907755278982137;  ///< log 1e-3
  static constexpr double kHighest = 20.72326583694641;  ///< log 1e9
  static constexpr double kTolerance = 1e-3;             ///< λ to 0.1%: the size is flat at that resolution
  struct Point {
    double log_lambda;
    std::size_t size;
  };
  LambdaBracket(std::size_t target, double guess) : target_(target), guess_(guess) {}
  /// @brief True when hi is known to fit and the bracket is narrower than kTolerance, or the
  /// lowest λ fits.
  bool done() const;
  /// @brief The two log λ to try next, in increasing order.
  std::array<double, 2> next() const;
  /// @brief Narrows the bracket with the sizes of the two values next() gave; returns the index
  /// (0 or 1) of the one that became hi, the best file so far, or −1.
  int update(const std::array<Point, 2>& tried);

 private:
  std::size_t target_;
  double guess_;
  double lo_ = kLowest, hi_ = kHighest;
  double lo_log_size_ = 0, hi_log_size_ = 0;
  bool lo_tried_ = false, hi_tried_ = false, lowest_fits_ = false, trisect_ = false;
  double slope_ = -0.5;  ///< d log size / d log λ of the last round, for extrapolation
  int rounds_ = 0;
};

}  // namespace ifsforge
