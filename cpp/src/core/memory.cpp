#include "ifsforge/core/memory.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "ifsforge/core/error.h"

namespace ifsforge {

std::size_t memory_budget() {
  if (const char* mb = std::getenv("IFSFORGE_MEMORY_BUDGET_MB")) {
    const double value = std::atof(mb);
    if (value > 0) return static_cast<std::size_t>(value * 1024.0 * 1024.0);
  }
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page <= 0) return std::size_t(4) << 30;
  return static_cast<std::size_t>(0.75 * static_cast<double>(pages) * static_cast<double>(page));
}

void check_memory(double bytes, const std::string& what) {
  const double budget = static_cast<double>(memory_budget());
  if (!(bytes <= budget)) {
    char message[512];
    std::snprintf(message, sizeof message,
                  "%s would need %.1f GiB of memory, more than the budget of %.1f GiB "
                  "(set IFSFORGE_MEMORY_BUDGET_MB to change it); nothing was allocated",
                  what.c_str(), bytes / 1073741824.0, budget / 1073741824.0);
    throw MemoryBudgetError(message);
  }
}

}  // namespace ifsforge
