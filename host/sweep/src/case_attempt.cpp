#include "clothlab/sweep/case_attempt.hpp"

#include <clothlab/host/errors.hpp>
#include <exception>
#include <new>

namespace clothlab::sweep {
namespace {

CaseResult failed_verdict(const std::exception_ptr& error) {
  CaseResult failed;
  failed.status = CaseStatus::Failed;
  try {
    std::rethrow_exception(error);
  } catch (const std::bad_alloc&) {
    failed.reason = "out of memory";
  } catch (const std::exception& exception) {
    failed.reason = host::one_line(exception.what());
  } catch (...) {
    failed.reason = "unknown exception";
  }
  return failed;
}

}  // namespace

CaseResult attempt_case(const CaseRunner& runner, const CaseSpec& c) {
  try {
    return runner(c);
  } catch (...) {
    return failed_verdict(std::current_exception());
  }
}

Trajectory attempt_trajectory(const TrajectoryRunner& runner, const CaseSpec& c) {
  try {
    return runner(c);
  } catch (...) {
    Trajectory failed;
    failed.verdict = failed_verdict(std::current_exception());
    return failed;
  }
}

}  // namespace clothlab::sweep
