#include "clothlab/analysis/find_max_dt.hpp"

#include "clothlab/analysis/bracket_search.hpp"

namespace clothlab::analysis {
namespace {

MaxDtOutcome outcome_of(BracketOutcome outcome) {
  switch (outcome) {
    case BracketOutcome::AllBelow:
      return MaxDtOutcome::AllStable;
    case BracketOutcome::AllAbove:
      return MaxDtOutcome::NoneStable;
    case BracketOutcome::OutOfEvaluations:
      return MaxDtOutcome::OutOfEvaluations;
    case BracketOutcome::Bracketed:
    case BracketOutcome::Stopped:  // never: a stability verdict has no stop
      break;
  }
  return MaxDtOutcome::Bracketed;
}

}  // namespace

const char* to_string(MaxDtOutcome outcome) {
  switch (outcome) {
    case MaxDtOutcome::Bracketed:
      return "bracketed";
    case MaxDtOutcome::AllStable:
      return "all-stable";
    case MaxDtOutcome::NoneStable:
      return "none-stable";
    case MaxDtOutcome::OutOfEvaluations:
      return "out-of-evaluations";
  }
  return "unknown";
}

MaxDtResult find_max_dt(const std::function<bool(double dt)>& is_stable,
                        const MaxDtOptions& options) {
  // A stable step lies below the limit, an unstable one above it.
  const BracketResult search =
      bracket_search([&](double dt, double) { return is_stable(dt) ? Side::below : Side::above; },
                     {.start = options.dt_initial,
                      .lower_limit = options.dt_lower_limit,
                      .upper_limit = options.dt_upper_limit,
                      .growth = options.growth,
                      .relative_tolerance = options.relative_tolerance,
                      .max_evaluations = options.max_evaluations});
  return {outcome_of(search.outcome), search.low, search.high, search.evaluations};
}

}  // namespace clothlab::analysis
