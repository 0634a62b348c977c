#include "clothlab/analysis/find_max_dt.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace clothlab::analysis {
namespace {

TEST(FindMaxDt, BracketsAThresholdToTheRelativeTolerance) {
  const double limit = 0.0137;
  MaxDtOptions options;
  options.dt_initial = 1e-3;
  options.relative_tolerance = 0.01;
  const MaxDtResult result = find_max_dt([&](double dt) { return dt <= limit; }, options);
  EXPECT_EQ(result.outcome, MaxDtOutcome::Bracketed);
  EXPECT_LE(result.dt_stable, limit);
  EXPECT_GT(result.dt_unstable, limit);
  EXPECT_LE(result.dt_unstable - result.dt_stable, 0.01 * result.dt_stable);
}

TEST(FindMaxDt, WalksDownFromAnUnstableGuess) {
  const double limit = 3e-5;
  MaxDtOptions options;
  options.dt_initial = 0.02;
  const MaxDtResult result = find_max_dt([&](double dt) { return dt < limit; }, options);
  EXPECT_EQ(result.outcome, MaxDtOutcome::Bracketed);
  EXPECT_LT(result.dt_stable, limit);
  EXPECT_GE(result.dt_unstable, limit);
  EXPECT_LE(result.dt_unstable - result.dt_stable, options.relative_tolerance * result.dt_stable);
}

TEST(FindMaxDt, ReportsAllStableAndNoneStable) {
  MaxDtOptions options;
  options.dt_upper_limit = 0.05;
  const MaxDtResult all = find_max_dt([](double) { return true; }, options);
  EXPECT_EQ(all.outcome, MaxDtOutcome::AllStable);
  EXPECT_DOUBLE_EQ(all.dt_stable, 0.05);

  const MaxDtResult none = find_max_dt([](double) { return false; }, options);
  EXPECT_EQ(none.outcome, MaxDtOutcome::NoneStable);
  EXPECT_DOUBLE_EQ(none.dt_stable, 0.0);
  EXPECT_DOUBLE_EQ(none.dt_unstable, options.dt_lower_limit);
}

TEST(FindMaxDt, StopsAtTheEvaluationBudget) {
  MaxDtOptions options;
  options.max_evaluations = 3;
  options.relative_tolerance = 1e-9;
  int calls = 0;
  const MaxDtResult result = find_max_dt(
      [&](double dt) {
        ++calls;
        return dt < 0.0123;
      },
      options);
  EXPECT_EQ(result.outcome, MaxDtOutcome::OutOfEvaluations);
  EXPECT_EQ(calls, 3);
  EXPECT_EQ(result.evaluations, 3);
}

TEST(FindMaxDt, RejectsOptionsOutOfRange) {
  MaxDtOptions options;
  options.relative_tolerance = 0.0;
  EXPECT_THROW(find_max_dt([](double) { return true; }, options), std::invalid_argument);
  options = {};
  options.dt_initial = 10.0;
  EXPECT_THROW(find_max_dt([](double) { return true; }, options), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab::analysis
