#include "clothlab/sweep/case_attempt.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <new>
#include <stdexcept>

namespace clothlab::sweep {
namespace {

CaseSpec a_case() {
  CaseSpec c;
  c.key = "integrator=euler";
  return c;
}

CaseResult verdict_of_throwing(const std::function<void()>& thrower) {
  const CaseRunner runner = [&](const CaseSpec&) -> CaseResult {
    thrower();
    return {};
  };
  return attempt_case(runner, a_case());
}

TEST(CaseAttempt, PassesTheRunnersResultThrough) {
  const CaseRunner runner = [](const CaseSpec&) {
    CaseResult result;
    result.status = CaseStatus::Unstable;
    result.check = "energy";
    return result;
  };
  const CaseResult result = attempt_case(runner, a_case());
  EXPECT_EQ(result.status, CaseStatus::Unstable);
  EXPECT_EQ(result.check, "energy");
}

TEST(CaseAttempt, AnExceptionBecomesAFailedVerdictWithItsMessageOnOneLine) {
  const CaseResult failed =
      verdict_of_throwing([] { throw std::runtime_error("crashed:\nsignal 11"); });
  EXPECT_EQ(failed.status, CaseStatus::Failed);
  EXPECT_EQ(failed.reason, "crashed:\\nsignal 11");
}

TEST(CaseAttempt, OutOfMemoryAndUnknownExceptionsAreNamed) {
  EXPECT_EQ(verdict_of_throwing([] { throw std::bad_alloc(); }).reason, "out of memory");
  const CaseResult unknown = verdict_of_throwing([] { throw 42; });
  EXPECT_EQ(unknown.status, CaseStatus::Failed);
  EXPECT_EQ(unknown.reason, "unknown exception");
}

TEST(CaseAttempt, AThrowingTrajectoryRunnerGivesAFailedTrajectoryWithoutPositions) {
  const TrajectoryRunner runner = [](const CaseSpec&) -> Trajectory {
    throw std::runtime_error("timed out after 5 s");
  };
  const Trajectory failed = attempt_trajectory(runner, a_case());
  EXPECT_EQ(failed.verdict.status, CaseStatus::Failed);
  EXPECT_EQ(failed.verdict.reason, "timed out after 5 s");
  EXPECT_TRUE(failed.positions.empty());
}

}  // namespace
}  // namespace clothlab::sweep
