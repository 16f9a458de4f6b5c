#pragma once
/// @file The memory budget: estimate before allocating, refuse with a clear message.
#include <cstddef>
#include <string>

namespace ifsforge {

/// @brief Bytes a single job may allocate: IFSFORGE_MEMORY_BUDGET_MB if set, else 75% of
/// the physical memory.
std::size_t memory_budget();

/// @brief Throws MemoryBudgetError naming `what` when `bytes` exceeds the budget.
void check_memory(double bytes, const std::string& what);

}  // namespace ifsforge
