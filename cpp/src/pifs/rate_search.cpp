#include "rate_search.h"

#include <algorithm>
#include <cmath>

namespace ifsforge {

double lambda_guess(const Image& image, std::size_t target) {
  const double samples = double(image.width) * image.height * image.channels;
  const double bits = std::max(1e-6, 8.0 * double(target) / samples);
  return std::clamp(4.8 - 2.2 * std::log(bits / 0.4), LambdaBracket::kLowest + 2, LambdaBracket::kHighest - 2);
}

bool LambdaBracket::done() const { return lowest_fits_ || (hi_tried_ && hi_ - lo_ <= kTolerance); }

std::array<double, 2> LambdaBracket::next() const {
  if (rounds_ == 0) return {guess_ - 1, guess_ + 1};
  const double width = hi_ - lo_;
  // Values strictly inside the bracket, or its end itself while that end is untried.
  const double low = lo_tried_ ? lo_ + kTolerance / 4 : lo_, high = hi_tried_ ? hi_ - kTolerance / 4 : hi_;
  if (!hi_tried_ && width <= kTolerance) return {std::min(high, lo_ + kTolerance / 4), high};
  if (trisect_) return {lo_ + width / 3, lo_ + 2 * width / 3};
  double at, spread;
  if (lo_tried_ && hi_tried_) {
    // lo's size is above the target and hi's within it: the fraction is in (0, 1].
    at = lo_ + width * (lo_log_size_ - std::log(double(target_))) / (lo_log_size_ - hi_log_size_);
    spread = std::max(0.4 * kTolerance, 0.06 * width);
  } else {
    const double from = lo_tried_ ? lo_ : hi_, from_size = lo_tried_ ? lo_log_size_ : hi_log_size_;
    at = from + (std::log(double(target_)) - from_size) / slope_;
    spread = 0.25 * std::abs(at - from) + 0.5;  // an extrapolation: less sure
  }
  double a = std::clamp(at - spread, low, high), b = std::clamp(at + spread, low, high);
  // Both clamped to one end (the target lies beyond it): the second value halves the bracket.
  if (b - a < kTolerance / 4) {
    if (b >= high) a = std::max(low, high - (high - low) / 2);
    else b = std::min(high, low + (high - low) / 2);
  }
  return {a, b};
}

int LambdaBracket::update(const std::array<Point, 2>& tried) {
  const double before = hi_ - lo_;
  const Point& p = tried[0];
  const Point& q = tried[1];
  if (p.size > 0 && q.size > 0 && p.size != q.size && q.log_lambda != p.log_lambda) {
    const double slope = (std::log(double(q.size)) - std::log(double(p.size))) / (q.log_lambda - p.log_lambda);
    slope_ = slope < -0.05 ? slope : -0.5;
  }
  // hi: the lowest λ tried that fits; lo: the highest below it that does not.
  int fit = -1;
  for (int i = 0; i < 2; ++i) {
    const Point& t = tried[std::size_t(i)];
    const bool below_hi = hi_tried_ ? t.log_lambda < hi_ : t.log_lambda <= hi_;
    if (t.size <= target_ && below_hi && t.log_lambda >= lo_ && (fit < 0 || t.log_lambda < tried[std::size_t(fit)].log_lambda))
      fit = i;
  }
  if (fit >= 0) {
    const Point& t = tried[std::size_t(fit)];
    hi_ = t.log_lambda;
    hi_log_size_ = std::log(double(std::max<std::size_t>(1, t.size)));
    hi_tried_ = true;
    lowest_fits_ = t.log_lambda <= kLowest;
  }
  for (const Point& t : tried) {
    const bool above_lo = lo_tried_ ? t.log_lambda > lo_ : t.log_lambda >= lo_;
    if (t.size > target_ && above_lo && t.log_lambda < hi_) {
      lo_ = t.log_lambda;
      lo_log_size_ = std::log(double(t.size));
      lo_tried_ = true;
    }
  }
  trisect_ = rounds_ > 0 && hi_ - lo_ > 0.5 * before;
  ++rounds_;
  return fit;
}

}  // namespace ifsforge
