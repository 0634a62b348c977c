#include "clothlab/analysis/find_max_dt.hpp"

#include <cmath>
#include <stdexcept>

namespace clothlab::analysis {
namespace {

void validate(const MaxDtOptions& options) {
  auto fail = [](const char* key, double value, const char* allowed) {
    throw std::invalid_argument(std::string("find_max_dt: ") + key + " = " + std::to_string(value) +
                                ", allowed " + allowed);
  };
  if (!(options.dt_lower_limit > 0.0)) fail("dt_lower_limit", options.dt_lower_limit, "> 0");
  if (!(options.dt_upper_limit > options.dt_lower_limit)) {
    fail("dt_upper_limit", options.dt_upper_limit, "> dt_lower_limit");
  }
  if (!(options.dt_initial >= options.dt_lower_limit &&
        options.dt_initial <= options.dt_upper_limit)) {
    fail("dt_initial", options.dt_initial, "in [dt_lower_limit, dt_upper_limit]");
  }
  if (!(options.relative_tolerance > 0.0 && options.relative_tolerance < 1.0)) {
    fail("relative_tolerance", options.relative_tolerance, "in (0, 1)");
  }
  if (!(options.growth > 1.0)) fail("growth", options.growth, "> 1");
  if (options.max_evaluations < 1) fail("max_evaluations", options.max_evaluations, ">= 1");
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
  validate(options);
  MaxDtResult result;
  auto probe = [&](double dt) {
    ++result.evaluations;
    const bool stable = is_stable(dt);
    if (stable) {
      result.dt_stable = dt;
    } else {
      result.dt_unstable = dt;
    }
    return stable;
  };
  auto out_of_evaluations = [&] { return result.evaluations >= options.max_evaluations; };

  // Bracket: walk up from a stable guess, or down from an unstable one.
  double dt = options.dt_initial;
  if (probe(dt)) {
    while (result.dt_unstable == 0.0) {
      if (dt >= options.dt_upper_limit) {
        result.outcome = MaxDtOutcome::AllStable;
        return result;
      }
      if (out_of_evaluations()) {
        result.outcome = MaxDtOutcome::OutOfEvaluations;
        return result;
      }
      dt = std::min(dt * options.growth, options.dt_upper_limit);
      probe(dt);
    }
  } else {
    while (result.dt_stable == 0.0) {
      if (dt <= options.dt_lower_limit) {
        result.outcome = MaxDtOutcome::NoneStable;
        return result;
      }
      if (out_of_evaluations()) {
        result.outcome = MaxDtOutcome::OutOfEvaluations;
        return result;
      }
      dt = std::max(dt / options.growth, options.dt_lower_limit);
      probe(dt);
    }
  }

  // Bisect in log(dt) between the largest stable and the smallest unstable step.
  while (result.dt_unstable - result.dt_stable > options.relative_tolerance * result.dt_stable) {
    if (out_of_evaluations()) {
      result.outcome = MaxDtOutcome::OutOfEvaluations;
      return result;
    }
    probe(std::sqrt(result.dt_stable * result.dt_unstable));
  }
  result.outcome = MaxDtOutcome::Bracketed;
  return result;
}

}  // namespace clothlab::analysis
