#pragma once
// The rate control's round as one job list (encoder.cpp): every unit (one plane of one probe)
// has a first step, then many independent middle steps, each followed, in order, by a
// sequential step (the entropy coder's share of that item).
#include <cstddef>
#include <functional>
#include <vector>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// @brief Runs, on `threads` threads in one parallel_jobs call, first(u) for every unit u, then
/// middle(u, i) for i in [0, middles[u]) once first(u) has ended, and follow(u, i) for i in
/// increasing order, each once middle(u, i) has ended, one follow of a unit at a time. Units are
/// listed costliest first and served in that order: a thread that ends a step takes the
/// first unit's next follow when it is ready and no thread runs one, else that unit's lowest
/// middle not yet taken (one a running follow will need), else the next unit's. So the costliest
/// unit's sequential follows start as soon as they can and the other threads quantise ahead of
/// them; no thread waits for a barrier, and a follow never waits while other work is ready.
/// Each step writes its own unit's results, so the outputs never depend on the thread count.
void staged_jobs(const std::vector<std::size_t>& middles, int threads,
                 const std::function<void(std::size_t unit)>& first,
                 const std::function<void(std::size_t unit, std::size_t item)>& middle,
                 const std::function<void(std::size_t unit, std::size_t item)>& follow,
                 const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
