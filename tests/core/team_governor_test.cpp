// The adaptive thread team (team_governor.hpp): when a step on the team got less than its share
// of CPU the steps after it run on the calling thread, for a hold that doubles while tries of
// the team still find a core taken and falls back once one gets its share. That the engine's
// steps give the same bits either way: fused_step_test.cpp, FusedStepAdaptiveTeam.
#include <gtest/gtest.h>

#include <clothlab/core/team_governor.hpp>
#include <vector>

namespace clothlab {
namespace {

constexpr double kWall = 1e-3;
constexpr double kFullShare = 2 * kWall;  // two threads that both had their core
constexpr double kHalfShare = kWall;      // one of them waited for a core the whole step

// Steps that run on one thread before the team is tried again.
int solo_steps_after(TeamGovernor& governor, double cpu_s) {
  EXPECT_TRUE(governor.team_step());
  governor.finished(kWall, cpu_s);
  int solo = 0;
  while (!governor.team_step()) {
    governor.finished(kWall, 0.5 * kWall);
    ++solo;
    if (solo > 1000) break;
  }
  return solo;
}

TEST(TeamGovernor, AStepThatGotItsShareKeepsTheTeam) {
  TeamGovernor governor(2, true);
  for (int step = 0; step < 10; ++step) EXPECT_EQ(solo_steps_after(governor, kFullShare), 0);
}

TEST(TeamGovernor, AStepThatLostACoreRunsTheNextOnesAloneForAHoldThatDoubles) {
  TeamGovernor governor(2, true);
  std::vector<int> holds;
  for (int try_count = 0; try_count < 9; ++try_count)
    holds.push_back(solo_steps_after(governor, kHalfShare));
  EXPECT_EQ(holds, (std::vector<int>{4, 8, 16, 32, 64, 128, 256, 256, 256}));
  // A try that gets its share: the team stays, and the next loss holds for the least again.
  EXPECT_EQ(solo_steps_after(governor, kFullShare), 0);
  EXPECT_EQ(solo_steps_after(governor, kHalfShare), 4);
}

TEST(TeamGovernor, JustBelowTheLeastShareIsALossJustAboveIsNot) {
  TeamGovernor governor(2, true);
  EXPECT_EQ(solo_steps_after(governor, 1.01 * TeamGovernor::kLeastShare * kFullShare), 0);
  EXPECT_EQ(solo_steps_after(governor, 0.99 * TeamGovernor::kLeastShare * kFullShare), 4);
}

TEST(TeamGovernor, OneThreadOrDisabledAlwaysRunsTheTeam) {
  TeamGovernor one(1, true), disabled(2, false);
  EXPECT_EQ(solo_steps_after(one, 0.0), 0);
  EXPECT_EQ(solo_steps_after(disabled, 0.0), 0);
}

}  // namespace
}  // namespace clothlab
