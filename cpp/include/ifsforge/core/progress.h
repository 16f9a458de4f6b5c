#pragma once
/// @file Progress reporting and cancellation for long work.
#include <cstddef>
#include <functional>

#include "ifsforge/core/error.h"

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

/// @brief Lets a long serial loop hear Ctrl-C: at every 2^20th `item`, calls poll(0) (a
/// progress_range fixed where the loop sits) and throws Cancelled when it says stop.
inline void poll_now_and_then(std::size_t item, const ProgressCallback& poll) {
  if ((item & 0xFFFFF) == 0 && poll && !poll(0.0)) throw Cancelled();
}

}  // namespace ifsforge
