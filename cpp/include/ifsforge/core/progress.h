#pragma once
/// @file Progress reporting and cancellation for long work.
#include <functional>

namespace ifsforge {

/// @brief Called with the fraction done in [0, 1]; returns false to cancel the work.
/// Only the thread that started the work calls it, never a worker.
using ProgressCallback = std::function<bool(double fraction)>;

/// @brief `progress` for one part [lo, hi] of the work: fraction f reports lo + f (hi - lo).
/// Empty when `progress` is.
inline ProgressCallback progress_span(const ProgressCallback& progress, double lo, double hi) {
  if (!progress) return nullptr;
  return [progress, lo, hi](double fraction) { return progress(lo + fraction * (hi - lo)); };
}

}  // namespace ifsforge
