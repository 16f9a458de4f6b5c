#pragma once
/// @file Drawing a map index with the system's probabilities in O(1) (Walker's alias method).
#include <cstdint>
#include <vector>

namespace ifsforge {

class MapSampler {
 public:
  explicit MapSampler(const std::vector<double>& probabilities);
  /// @brief A map index for one 64-bit uniform random word.
  std::uint32_t operator()(std::uint64_t random) const {
    const std::uint32_t column = static_cast<std::uint32_t>(((random >> 32) * size_) >> 32);
    // A mask, not a branch: where columns are split (a recurrent row, unequal probabilities)
    // the choice is a coin toss that a branch predictor misses half the time.
    const std::uint32_t keep = 0u - std::uint32_t(static_cast<std::uint32_t>(random) < threshold_[column]);
    return (column & keep) | (alias_[column] & ~keep);
  }
  std::size_t size() const { return size_; }
  /// @brief Column `column`'s split: the low word below threshold(column) keeps the column,
  /// else alias(column) (what a vector kernel draws from, the same way).
  std::uint32_t threshold(std::uint32_t column) const { return threshold_[column]; }
  std::uint32_t alias(std::uint32_t column) const { return alias_[column]; }

 private:
  std::uint64_t size_;
  std::vector<std::uint32_t> threshold_;  ///< keep `column` when the low word is below this
  std::vector<std::uint32_t> alias_;
};

}  // namespace ifsforge
