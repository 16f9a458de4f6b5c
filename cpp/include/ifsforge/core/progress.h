#pragma once
/// @file Progress reporting and cancellation for long work.
#include <functional>

namespace ifsforge {

/// @brief Called with the fraction done in [0, 1]; returns false to cancel the work.
/// Only the thread that started the work calls it, never a worker.
using ProgressCallback = std::function<bool(double fraction)>;

/// @brief `progress` for one part [from, to] of the work: fraction f reports
/// from + f (to - from). Empty when `progress` is.
inline ProgressCallback progress_range(const ProgressCallback& progress, double from, double to) {
  if (!progress) return nullptr;
  return [progress, from, to](double fraction) { return progress(from + fraction * (to - from)); };
}

}  // namespace ifsforge
