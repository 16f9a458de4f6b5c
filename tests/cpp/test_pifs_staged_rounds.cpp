// The rate control's job lists (cpp/src/pifs/staged_rounds.h): on any number of threads every step
// of every round runs once, each part after its unit's first and after every part of the stage
// before, each middle after its unit's last stage, each follow after its middle, in order and
// never beside another follow of its unit; a round starts only once the one before has ended,
// and no step runs beside next_round.
#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <mutex>
#include <thread>
#include <vector>

#include "../../cpp/src/pifs/staged_rounds.h"

using namespace ifsforge;

TEST(PifsStagedJobs, EveryStepOnceAndInOrderOnAnyThreadCount) {
  const std::vector<std::vector<std::size_t>> rounds = {{40, 0, 7, 25, 1}, {}, {3}, {0, 0}, {12, 30}};
  // The stages first(u) answers, unit by unit (a unit past the list has none): empty stages,
  // stages without middles after them, more parts than threads.
  const std::vector<std::vector<std::vector<std::size_t>>> stages = {
      {{3, 1, 5}, {}, {0, 2}, {9}, {1, 0, 0}}, {}, {{2, 2}}, {{4}, {}}, {{}, {6, 6, 6}}};
  for (int threads : {1, 2, 3, 7}) {
    std::size_t round = 0;
    std::vector<std::size_t> middles;
    std::vector<std::atomic<int>> firsts, following;
    std::vector<std::vector<std::atomic<int>>> done;
    std::vector<std::vector<std::size_t>> followed;
    // Per unit: the parts of each stage that have ended.
    std::vector<std::vector<std::size_t>> parts_done;
    std::mutex mutex;
    bool ordered = true;
    std::atomic<bool> beside{false}, between{false};
    // Checks the round that ended; then starts the next.
    const auto check_round = [&] {
      for (std::size_t u = 0; u < middles.size(); ++u) {
        EXPECT_EQ(firsts[u], 1) << threads << " threads, round " << round << ", unit " << u;
        for (std::size_t i = 0; i < middles[u]; ++i) EXPECT_EQ(done[u][i], 1) << threads << " threads, unit " << u;
        const std::vector<std::size_t> asked = u < stages[round - 1].size() ? stages[round - 1][u] : std::vector<std::size_t>{};
        EXPECT_EQ(parts_done[u], asked) << threads << " threads, round " << round << ", unit " << u;
        std::vector<std::size_t> in_order(middles[u]);
        for (std::size_t i = 0; i < middles[u]; ++i) in_order[i] = i;
        EXPECT_EQ(followed[u], in_order) << threads << " threads, round " << round << ", unit " << u;
      }
    };
    staged_rounds(
        [&](std::vector<std::size_t>& next) {
          between = true;
          if (round > 0) check_round();
          if (round == rounds.size()) return false;
          middles = next = rounds[round++];
          firsts = std::vector<std::atomic<int>>(middles.size());
          following = std::vector<std::atomic<int>>(middles.size());
          done = std::vector<std::vector<std::atomic<int>>>(middles.size());
          for (std::size_t u = 0; u < middles.size(); ++u) done[u] = std::vector<std::atomic<int>>(middles[u]);
          followed.assign(middles.size(), {});
          parts_done.assign(middles.size(), {});
          for (std::size_t u = 0; u < middles.size() && u < stages[round - 1].size(); ++u)
            parts_done[u].assign(stages[round - 1][u].size(), 0);
          between = false;
          return true;
        },
        threads,
        [&](std::size_t u) {
          if (between) beside = true;
          ++firsts[u];
          return u < stages[round - 1].size() ? stages[round - 1][u] : std::vector<std::size_t>{};
        },
        [&](std::size_t u, std::size_t stage, std::size_t) {
          const std::vector<std::size_t>& asked = stages[round - 1][u];
          {
            std::lock_guard<std::mutex> lock(mutex);
            ordered = ordered && firsts[u] == 1 && !between && stage < asked.size();
            for (std::size_t s = 0; s < stage && ordered; ++s) ordered = parts_done[u][s] == asked[s];
          }
          std::this_thread::yield();  // the stage's other parts may run meanwhile
          std::lock_guard<std::mutex> lock(mutex);
          if (stage < asked.size()) ++parts_done[u][stage];
        },
        [&](std::size_t u, std::size_t i) {
          std::lock_guard<std::mutex> lock(mutex);
          ordered = ordered && firsts[u] == 1 && !between;
          if (u < stages[round - 1].size()) ordered = ordered && parts_done[u] == stages[round - 1][u];
          ++done[u][i];
        },
        [&](std::size_t u, std::size_t i) {
          if (following[u]++ != 0 || between) beside = true;
          {
            std::lock_guard<std::mutex> lock(mutex);
            ordered = ordered && done[u][i] == 1;
            followed[u].push_back(i);
          }
          --following[u];
        });
    EXPECT_EQ(round, rounds.size()) << threads << " threads";
    EXPECT_TRUE(ordered) << threads << " threads";
    EXPECT_FALSE(beside) << threads << " threads";
  }
}
