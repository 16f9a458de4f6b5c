#pragma once
/// @file Progress reporting and cancellation for long work.
#include <functional>

namespace ifsforge {

/// @brief Called with the fraction done in [0, 1]; returns false to cancel the work.
/// Only the thread that started the work calls it, never a worker.
using ProgressCallback = std::function<bool(double fraction)>;

}  // namespace ifsforge
