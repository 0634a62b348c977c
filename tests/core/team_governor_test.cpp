// The adaptive thread team (team_governor.hpp): team steps with a probe of a few steps on one
// thread now and then, alone for a hold when the probe beats the team, back to the team when
// its tries are clearly faster. That the engine's steps give the same bits either way:
// fused_step_test.cpp, FusedStepAdaptiveTeam.
#include <gtest/gtest.h>

#include <clothlab/core/team_governor.hpp>
#include <string>
#include <vector>

namespace clothlab {
namespace {

// A machine on which a team step takes `team_s` and a step alone `alone_s`; the governor's
// choices, step by step, as 'T' (team) and 'a' (alone).
struct Machine {
  double team_s, alone_s;

  std::string run(TeamGovernor& governor, int steps) const {
    std::string choices;
    for (int step = 0; step < steps; ++step) {
      const bool team = governor.team_step();
      choices += team ? 'T' : 'a';
      governor.finished(team ? team_s : alone_s);
    }
    return choices;
  }
};

// Where each run of 'a' in a choice string starts, and how long it is.
struct AloneRuns {
  std::vector<std::size_t> starts;
  std::vector<int> lengths;
};

AloneRuns alone_runs(const std::string& choices) {
  AloneRuns runs;
  for (std::size_t step = 0; step < choices.size(); ++step) {
    if (choices[step] != 'a') continue;
    if (step == 0 || choices[step - 1] != 'a') {
      runs.starts.push_back(step);
      runs.lengths.push_back(0);
    }
    ++runs.lengths.back();
  }
  return runs;
}

TEST(TeamGovernor, AClearlyFasterTeamKeepsItsStepsAndProbesAtIntervalsThatDouble) {
  TeamGovernor governor(2, true);
  const AloneRuns runs = alone_runs(Machine{1e-3, 1.8e-3}.run(governor, 1000));
  // Probes of 3 steps after 16, 32, 64, 128, 256, 256 team steps.
  EXPECT_EQ(runs.starts, (std::vector<std::size_t>{16, 51, 118, 249, 508, 767}));
  EXPECT_EQ(runs.lengths, std::vector<int>(6, 3));
}

TEST(TeamGovernor, ACloseCallIsProbedAgainAfterTheLeastInterval) {
  TeamGovernor governor(2, true);
  // The team is faster, but not by the gain that would double the interval.
  const AloneRuns runs = alone_runs(Machine{1e-3, 1.05e-3}.run(governor, 100));
  EXPECT_EQ(runs.starts, (std::vector<std::size_t>{16, 35, 54, 73, 92}));
}

TEST(TeamGovernor, AFasterThreadAloneRunsHoldsThatDoubleBetweenTriesOfTheTeam) {
  TeamGovernor governor(2, true);
  const std::string choices = Machine{3e-3, 2e-3}.run(governor, 3000);
  EXPECT_EQ(choices.substr(0, 16), std::string(16, 'T'));
  const AloneRuns runs = alone_runs(choices);
  ASSERT_GE(runs.lengths.size(), 8u);
  // The probe, then its hold of 4, are one run; each later run is a hold after a failed try.
  EXPECT_EQ(std::vector<int>(runs.lengths.begin(), runs.lengths.begin() + 8),
            (std::vector<int>{7, 8, 16, 32, 64, 128, 256, 256}));
  // Each try is kTrySteps team steps.
  const std::string alone_team_alone = std::string(7, 'a').append("TTTT").append(8, 'a');
  EXPECT_NE(choices.find(alone_team_alone), std::string::npos);
}

TEST(TeamGovernor, ATeamStepMuchSlowerThanTheRecentOnesProbesAtOnce) {
  TeamGovernor governor(2, true);
  EXPECT_EQ((Machine{1e-3, 1.8e-3}.run(governor, 5)), "TTTTT");
  ASSERT_TRUE(governor.team_step());
  governor.finished(1.6e-3);  // slower than 1.5 x the mean of the last five
  // The probe loses to the slow step: the team goes on.
  EXPECT_EQ((Machine{1e-3, 1.8e-3}.run(governor, 4)), "aaaT");
}

TEST(TeamGovernor, JustUnderTheSlowStepBoundIsNoProbe) {
  TeamGovernor governor(2, true);
  EXPECT_EQ((Machine{1e-3, 1.8e-3}.run(governor, 5)), "TTTTT");
  governor.finished(1.49e-3);
  EXPECT_TRUE(governor.team_step());
}

// Alone after a probe that won (1 ms alone against 1.2 ms on the team); then the tries of a
// team that takes `team_s`.
std::string after_a_won_probe(double team_s) {
  TeamGovernor governor(2, true);
  const std::string probed = Machine{1.2e-3, 1e-3}.run(governor, 16 + 3);
  EXPECT_EQ(probed, std::string(16, 'T').append("aaa"));
  return Machine{team_s, 1e-3}.run(governor, 4 + 4 + 8);
}

TEST(TeamGovernor, TheTeamComesBackOnlyWhenClearlyFasterThanTheHold) {
  EXPECT_EQ(after_a_won_probe(0.89e-3), "aaaaTTTTTTTTTTTT");
  EXPECT_EQ(after_a_won_probe(0.91e-3), "aaaaTTTTaaaaaaaa");
}

TEST(TeamGovernor, ATryThatWinsHalvesTheHoldForTheNextLoss) {
  TeamGovernor governor(2, true);
  // Alone is faster: the probe's hold of 4, then holds of 8, 16, 32 after lost tries.
  const std::string lost = Machine{3e-3, 2e-3}.run(governor, 16 + 7 + 4 + 8 + 4 + 16 + 4 + 32);
  EXPECT_EQ(alone_runs(lost).lengths, (std::vector<int>{7, 8, 16, 32}));
  // The machine frees up: the next try wins and the team runs.
  const std::string won = Machine{1e-3, 2e-3}.run(governor, 4 + 15);
  EXPECT_EQ(won, std::string(19, 'T'));
  // The core is taken again: a slow team step, a probe that beats it, and a hold of 32 / 2
  // steps, not 4.
  const std::string again = Machine{3e-3, 2e-3}.run(governor, 1 + 3 + 16 + 1);
  EXPECT_EQ(again, "T" + std::string(3 + 16, 'a') + "T");
}

TEST(TeamGovernor, OneThreadOrDisabledAlwaysRunsTheTeam) {
  TeamGovernor one(1, true), disabled(2, false);
  const Machine busy{3e-3, 1e-3};
  EXPECT_EQ(busy.run(one, 300), std::string(300, 'T'));
  EXPECT_EQ(busy.run(disabled, 300), std::string(300, 'T'));
}

}  // namespace
}  // namespace clothlab
