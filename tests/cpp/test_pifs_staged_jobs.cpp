// The rate control's job list (cpp/src/pifs/staged_jobs.h): on any number of threads every step
// runs once, each middle after its unit's first, each follow after its middle, in order and
// never beside another follow of its unit.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <mutex>
#include <vector>

#include "../../cpp/src/pifs/staged_jobs.h"

using namespace ifsforge;

TEST(PifsStagedJobs, EveryStepOnceAndInOrderOnAnyThreadCount) {
  const std::vector<std::size_t> middles = {40, 0, 7, 25, 1};
  for (int threads : {1, 2, 3, 7}) {
    std::vector<std::atomic<int>> firsts(middles.size());
    std::vector<std::vector<std::atomic<int>>> done(middles.size());
    for (std::size_t u = 0; u < middles.size(); ++u) done[u] = std::vector<std::atomic<int>>(middles[u]);
    std::vector<std::vector<std::size_t>> followed(middles.size());
    std::vector<std::atomic<int>> following(middles.size());
    std::mutex mutex;
    bool ordered = true;
    std::atomic<bool> beside{false};
    staged_jobs(
        middles, threads, [&](std::size_t u) { ++firsts[u]; },
        [&](std::size_t u, std::size_t i) {
          std::lock_guard<std::mutex> lock(mutex);
          ordered = ordered && firsts[u] == 1;
          ++done[u][i];
        },
        [&](std::size_t u, std::size_t i) {
          if (following[u]++ != 0) beside = true;
          {
            std::lock_guard<std::mutex> lock(mutex);
            ordered = ordered && done[u][i] == 1;
            followed[u].push_back(i);
          }
          --following[u];
        });
    EXPECT_TRUE(ordered) << threads << " threads";
    EXPECT_FALSE(beside) << threads << " threads";
    for (std::size_t u = 0; u < middles.size(); ++u) {
      EXPECT_EQ(firsts[u], 1) << threads << " threads, unit " << u;
      for (std::size_t i = 0; i < middles[u]; ++i) EXPECT_EQ(done[u][i], 1) << threads << " threads, unit " << u;
      std::vector<std::size_t> in_order(middles[u]);
      for (std::size_t i = 0; i < middles[u]; ++i) in_order[i] = i;
      EXPECT_EQ(followed[u], in_order) << threads << " threads, unit " << u;
    }
  }
}
