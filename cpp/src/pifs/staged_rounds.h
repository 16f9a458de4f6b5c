#pragma once
// The encoder's rounds as job lists (encoder.cpp): the set-up (one unit: the planes' rasters,
// then their conversion, padding and halving, each a stage of parts), the domain search (a unit
// is a domain pool: built, then its block rows searched), then the rate control's (a unit is
// one plane of one probe: cut, then decoded a pass at a time, each pass in parts, then its
// residual's rows quantised, each followed, in order, by the entropy coder's share of that row).
#include <cstddef>
#include <functional>
#include <vector>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// @brief Runs round after round on `threads` threads in one parallel_jobs call (the threads
/// outlive the rounds). Before each round one thread calls next_round, which gives the round's
/// middles per unit (from the results of the rounds before it) or returns false when none is
/// left, while the other threads wait. In a round, first(u) runs for every unit u and returns
/// the unit's stages: stage s has that many parts, part(u, s, i) for every i, side by side on
/// any threads, each stage once the one before it has ended. Then middle(u, i) runs for i in
/// [0, middles[u]) once the last stage has ended, and follow(u, i) for i in increasing order,
/// each once middle(u, i) has ended, one follow of a unit at a time. Units are listed costliest
/// first and served in that order: a thread that ends a step takes the first unit's next part,
/// else its next follow when it is ready and no thread runs one, else that unit's lowest middle
/// not yet taken (one a running follow will need), else the next unit's. So the costliest
/// unit's stages run on every thread that is free and its sequential follows start as soon as
/// they can while the other threads quantise ahead of them; a thread waits within a round only
/// when no step of any unit is ready (a stage's last parts or a follow's middle still running),
/// and a follow never waits while other work is ready. A thread with nothing to do spins
/// briefly before it sleeps. Each step writes its own unit's results, so the outputs
/// never depend on the thread count. `progress` hears the rounds ended plus the running round's
/// share of steps ended.
void staged_rounds(const std::function<bool(std::vector<std::size_t>& middles)>& next_round, int threads,
                   const std::function<std::vector<std::size_t>(std::size_t unit)>& first,
                   const std::function<void(std::size_t unit, std::size_t stage, std::size_t part)>& part,
                   const std::function<void(std::size_t unit, std::size_t item)>& middle,
                   const std::function<void(std::size_t unit, std::size_t item)>& follow,
                   const ProgressCallback& progress = nullptr);

}  // namespace ifsforge
