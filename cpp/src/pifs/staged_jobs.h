#pragma once
// The rate control's round as one job list (encoder.cpp): every unit (one plane of one probe)
// has a first step, then many independent middle steps, then a last step, each on one thread.
#include <cstddef>
#include <functional>
#include <vector>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// @brief Runs, on `threads` threads in one parallel_jobs call, first(u) for every unit u, then
/// middle(u, i) for i in [0, middles[u]) once first(u) has ended, then last(u) once every middle
/// of u has ended. A thread that ends a step takes the next step whose inputs are ready,
/// whichever unit it belongs to: no thread waits for a barrier while another unit's work is
/// left, and a thread started late (a loaded machine) finds the work shared out anew. Each step
/// writes its own unit's results, so the outputs never depend on the thread count; the lasts,
/// often the longer sequential steps, run side by side at the end.
void staged_jobs(const std::vector<std::size_t>& middles, int threads,
                 const std::function<void(std::size_t unit)>& first,
                 const std::function<void(std::size_t unit, std::size_t item)>& middle,
                 const std::function<void(std::size_t unit)>& last, const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
