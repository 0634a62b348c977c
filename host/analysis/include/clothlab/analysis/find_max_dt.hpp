// Largest stable time step: bracket, then bisect a stability predicate (bracket_search.hpp).
#pragma once

#include <functional>
#include <string>

namespace clothlab::analysis {

struct MaxDtOptions {
  double dt_initial = 1e-3;          // first guess, s
  double dt_lower_limit = 1e-7;      // give up below: nothing stable
  double dt_upper_limit = 1.0;       // give up above: everything stable
  double relative_tolerance = 0.02;  // stop when (unstable - stable) <= tol * stable
  double growth = 2.0;               // bracketing factor
  int max_evaluations = 64;
};

enum class MaxDtOutcome {
  Bracketed,   // dt_stable < dt_max < dt_unstable, to the tolerance
  AllStable,   // stable up to dt_upper_limit
  NoneStable,  // unstable down to dt_lower_limit
  OutOfEvaluations
};
const char* to_string(MaxDtOutcome outcome);

struct MaxDtResult {
  MaxDtOutcome outcome = MaxDtOutcome::NoneStable;
  double dt_stable = 0.0;    // largest step seen stable (0 if none)
  double dt_unstable = 0.0;  // smallest step seen unstable (0 if none)
  int evaluations = 0;
};

// Assumes stability is monotone in dt (stable below the limit, unstable above). Bisects in
// log(dt) so the tolerance is relative at every scale. Throws std::invalid_argument on options
// out of range.
MaxDtResult find_max_dt(const std::function<bool(double dt)>& is_stable,
                        const MaxDtOptions& options);

}  // namespace clothlab::analysis
