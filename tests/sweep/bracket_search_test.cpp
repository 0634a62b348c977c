#include "clothlab/analysis/bracket_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace clothlab::analysis {
namespace {

// Below where x^3 - 7 < 0: the threshold is the cube root of 7.
Side cubic_side(double x, double) { return x * x * x - 7.0 < 0.0 ? Side::below : Side::above; }

BracketOptions range_1e3() { return {.start = 1.0, .lower_limit = 1e-3, .upper_limit = 1e3}; }

TEST(BracketSearch, FindsTheThresholdOfAMonotoneFunctionWithinTheTolerance) {
  BracketOptions options = range_1e3();
  options.relative_tolerance = 1e-6;
  const BracketResult result = bracket_search(cubic_side, options);
  const double root = std::cbrt(7.0);
  EXPECT_EQ(result.outcome, BracketOutcome::Bracketed);
  EXPECT_LT(result.low, root);
  EXPECT_GE(result.high, root);
  EXPECT_LE(result.high - result.low, 1e-6 * result.low);
  // Two probes bracket it in [1, 2]; each bisection halves log(high / low), from log 2 down to
  // log(1 + 1e-6): 20 halvings.
  EXPECT_LE(result.evaluations, 2 + 20);
}

TEST(BracketSearch, WalksDownFromAStartAboveTheThreshold) {
  BracketOptions options = range_1e3();
  options.start = 900.0;
  const BracketResult result = bracket_search(cubic_side, options);
  EXPECT_EQ(result.outcome, BracketOutcome::Bracketed);
  EXPECT_LT(result.low, std::cbrt(7.0));
  EXPECT_GE(result.high, std::cbrt(7.0));
}

TEST(BracketSearch, ReportsAPredicateThatNeverChangesAtTheLimits) {
  int calls = 0;
  const BracketResult never_above = bracket_search(
      [&](double, double) {
        ++calls;
        return Side::below;
      },
      {.start = 1.0, .lower_limit = 1.0, .upper_limit = 64.0});
  EXPECT_EQ(never_above.outcome, BracketOutcome::AllBelow);
  EXPECT_EQ(never_above.low, 64.0);
  EXPECT_EQ(never_above.high, 0.0);
  EXPECT_EQ(calls, 7);  // 1, 2, 4, ..., 64
  EXPECT_EQ(never_above.evaluations, 7);

  const BracketResult always_above =
      bracket_search([](double, double) { return Side::above; },
                     {.start = 8.0, .lower_limit = 1.0, .upper_limit = 64.0});
  EXPECT_EQ(always_above.outcome, BracketOutcome::AllAbove);
  EXPECT_EQ(always_above.low, 0.0);
  EXPECT_EQ(always_above.high, 1.0);
  EXPECT_EQ(always_above.evaluations, 4);  // 8, 4, 2, 1
}

TEST(BracketSearch, StopsAtTheEvaluationBudget) {
  BracketOptions options = range_1e3();
  options.relative_tolerance = 1e-9;
  options.max_evaluations = 5;
  int calls = 0;
  const BracketResult result = bracket_search(
      [&](double x, double low) {
        ++calls;
        return cubic_side(x, low);
      },
      options);
  EXPECT_EQ(result.outcome, BracketOutcome::OutOfEvaluations);
  EXPECT_EQ(calls, 5);
  EXPECT_EQ(result.evaluations, 5);
}

// The fewest whole n >= 37 passing: the below side fails, bisected at the middle to the unit.
TEST(BracketSearch, BisectsAWholeNumberToTheUnitAndTellsEachProbeTheBracketsBottom) {
  std::vector<std::pair<double, double>> probes;  // (n, low)
  const BracketResult result = bracket_search(
      [&](double n, double low) {
        probes.emplace_back(n, low);
        return n >= 37 ? Side::above : Side::below;
      },
      {.start = 1.0,
       .lower_limit = 1.0,
       .upper_limit = 4096.0,
       .relative_tolerance = 0.001,
       .resolution = 1.0,
       .bisect_at = [](double low, double high) { return std::floor((low + high) / 2); }});
  EXPECT_EQ(result.outcome, BracketOutcome::Bracketed);
  EXPECT_EQ(result.low, 36.0);
  EXPECT_EQ(result.high, 37.0);
  ASSERT_GE(probes.size(), 8u);
  EXPECT_EQ(probes[6], std::make_pair(64.0, 32.0));  // doubling: 1, 2, ..., 32 fail, 64 passes
  EXPECT_EQ(probes[7], std::make_pair(48.0, 32.0));
}

TEST(BracketSearch, AProbeOrARuleCanEndTheSearch) {
  // A stop in the bisection keeps the bracket found so far and names the value: [1, 2], then
  // the first bisection at sqrt 2 stops.
  const BracketResult stopped = bracket_search(
      [](double x, double) { return x > 1.3 && x < 1.5 ? Side::stop : cubic_side(x, 0); },
      range_1e3());
  EXPECT_EQ(stopped.outcome, BracketOutcome::Stopped);
  EXPECT_EQ(stopped.low, 1.0);
  EXPECT_EQ(stopped.high, 2.0);
  EXPECT_DOUBLE_EQ(stopped.stopped_at, std::sqrt(2.0));

  BracketOptions unrefined = range_1e3();
  unrefined.bisect_at = [](double, double) { return std::nullopt; };
  const BracketResult ended = bracket_search(cubic_side, unrefined);
  EXPECT_EQ(ended.outcome, BracketOutcome::Stopped);
  EXPECT_EQ(ended.high, 2.0);
  EXPECT_EQ(ended.stopped_at, 0.0);

  BracketOptions walk_once = range_1e3();
  walk_once.start = 0.5;
  walk_once.keep_bracketing = [] { return false; };
  const BracketResult abandoned = bracket_search(cubic_side, walk_once);
  EXPECT_EQ(abandoned.outcome, BracketOutcome::Stopped);
  EXPECT_EQ(abandoned.evaluations, 1);
}

TEST(BracketSearch, RejectsOptionsOutOfRange) {
  BracketOptions options = range_1e3();
  options.growth = 1.0;
  EXPECT_THROW(bracket_search(cubic_side, options), std::invalid_argument);
  options = range_1e3();
  options.start = 1e4;
  EXPECT_THROW(bracket_search(cubic_side, options), std::invalid_argument);
  options = range_1e3();
  options.relative_tolerance = 0.0;
  EXPECT_THROW(bracket_search(cubic_side, options), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab::analysis
