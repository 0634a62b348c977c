// One attempt at a case: whatever the runner throws becomes a Failed verdict, so that one bad
// case is a row of the results and the sweep, search or choice goes on.
#pragma once

#include "clothlab/sweep/case_result.hpp"
#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/sweep_runner.hpp"
#include "clothlab/sweep/work_precision.hpp"

namespace clothlab::sweep {

// What the verdict of a throwing runner says: status Failed and as reason
//   - std::bad_alloc: "out of memory" (its what() names only the type);
//   - any other std::exception: its message on one line (a row's reason is one line, and a
//     child's message may echo a value with line breaks);
//   - anything else: "unknown exception".

// runner(c), or a result with only that verdict.
CaseResult attempt_case(const CaseRunner& runner, const CaseSpec& c);
// runner(c), or a trajectory with no positions and that verdict.
Trajectory attempt_trajectory(const TrajectoryRunner& runner, const CaseSpec& c);

}  // namespace clothlab::sweep
