// The rate control's λ search (cpp/src/pifs/rate_search.h) on size curves written here: it ends
// with the largest file within the target to 0.1% of log λ, in few rounds on a curve like a
// photograph's, in a bounded number on a staircase, and at either end of the λ range when the
// target lies beyond it.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <vector>

#include "../../cpp/src/pifs/rate_search.h"

using namespace ifsforge;

namespace {

struct Outcome {
  int rounds = 0;
  bool beyond_highest = false;  ///< a value at the highest λ did not fit (the encoder refuses)
  LambdaBracket::Point best{0, 0};
  double lo = 0;  ///< the highest log λ tried below best that did not fit
};

/// The encoder's loop over a size curve `size(log λ)`.
Outcome search(std::size_t target, double guess, const std::function<std::size_t(double)>& size) {
  LambdaBracket bracket(target, guess);
  Outcome out;
  out.lo = LambdaBracket::kLowest;
  std::vector<LambdaBracket::Point> tried;
  while (!bracket.done() && out.rounds < 100) {
    const std::array<double, 2> next = bracket.next();
    EXPECT_LE(next[0], next[1]);
    const std::array<LambdaBracket::Point, 2> round{{{next[0], size(next[0])}, {next[1], size(next[1])}}};
    ++out.rounds;
    for (const auto& p : round) {
      tried.push_back(p);
      if (p.log_lambda >= LambdaBracket::kHighest && p.size > target) out.beyond_highest = true;
    }
    if (out.beyond_highest) return out;
    const int fit = bracket.update(round);
    if (fit >= 0) out.best = round[std::size_t(fit)];
  }
  for (const auto& p : tried)
    if (p.size > target && p.log_lambda < out.best.log_lambda) out.lo = std::max(out.lo, p.log_lambda);
  return out;
}

/// A photograph's curve: log size linear in log λ with a gentle bend, as measured on camera, down
/// to the smallest code (200 bytes).
std::size_t smooth(double x) { return std::max<std::size_t>(200, std::size_t(std::exp(12.0 - 0.55 * x - 0.01 * x * x))); }

}  // namespace

TEST(PifsRateSearch, FindsTheLargestFileWithinTheTargetInFewRounds) {
  for (double guess : {-4.0, 2.0, 7.0, 15.0}) {
    const std::size_t target = 5000;
    const Outcome o = search(target, guess, smooth);
    ASSERT_FALSE(o.beyond_highest);
    EXPECT_LE(o.best.size, target);
    EXPECT_GT(smooth(o.best.log_lambda - LambdaBracket::kTolerance), target) << "guess " << guess;
    EXPECT_LE(o.best.log_lambda - o.lo, LambdaBracket::kTolerance);
    EXPECT_LE(o.rounds, 8) << "guess " << guess;
  }
}

TEST(PifsRateSearch, EndsOnAStaircase) {
  // Sizes flat over whole units of log λ: interpolation learns nothing there, trisection ends it.
  const auto stairs = [](double x) { return std::size_t(1000 * (30 - std::floor(x))); };
  const Outcome o = search(14500, 3.0, stairs);
  EXPECT_EQ(o.best.size, 14000u);
  EXPECT_LE(o.best.log_lambda - o.lo, LambdaBracket::kTolerance);
  EXPECT_LT(o.rounds, 30);
}

TEST(PifsRateSearch, ReachesEitherEndOfTheRange) {
  // A target below the smallest file: the highest λ is tried, and the encoder refuses.
  EXPECT_TRUE(search(10, 3.0, smooth).beyond_highest);
  // A target above the largest: the lowest λ's file is kept.
  const Outcome o = search(std::size_t(1) << 40, 3.0, smooth);
  EXPECT_FALSE(o.beyond_highest);
  EXPECT_EQ(o.best.log_lambda, LambdaBracket::kLowest);
}
