// Work-precision: error at time T against a float64 reference, per integrator and dt ladder.
//
// For each problem (the case's coordinates without integrator and precision) the reference is
// the reference integrator in float64 at dt_ref = (finest ladder dt) / refinement, checked by
// one more halving: the finer run is used as the reference, and the difference between the two,
// over the cloth diagonal, is reported (divided by 15 it estimates the finer run's own error
// for an order-4 method). Each (integrator, precision) case then runs the ladder
// dt_start / 2^k, k = 0 .. levels-1, to T = the sweep's duration exactly (steps = T / dt).
//   error = sqrt(mean over particles of |x - x_ref|^2) / diagonal
// and the empirical order is fitted over the automatically chosen asymptotic range.
// Integrators listed in self_reference solve another ODE than the reference (position Verlet
// has no velocity forces and its own drag): their reference is themselves at dt_ref, per problem.
#pragma once

#include <clothlab/host/run_summary.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "clothlab/sweep/case_result.hpp"
#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/progress.hpp"
#include "clothlab/sweep/results_store.hpp"

namespace clothlab::sweep {

struct Trajectory {
  std::vector<double> positions;  // final positions, particle-major (3 per particle)
  double diagonal = 0.0;          // cloth diagonal, m (sqrt(width^2 + height^2))
  // The run's figures; a run that failed (an exception, a timeout) has the defaults.
  host::RunSummary summary;
  CaseResult verdict;  // status Stable, or Unstable/Failed with step and reason
};
// Runs the case (its dt, precision and steps settings are set by the driver) to the end.
using TrajectoryRunner = std::function<Trajectory(const CaseSpec&)>;

// RMS particle distance over the diagonal; throws SweepError on mismatched sizes.
double relative_rms_error(const std::vector<double>& positions,
                          const std::vector<double>& reference, double diagonal);

struct WorkPrecisionSummary {
  std::size_t references = 0;  // computed in this session
  std::size_t runs = 0;        // ladder runs in this session
  std::size_t skipped = 0;     // ladder rows already stored
};

// Rows (all keys start with "work-precision;"):
//   kind=reference: problem coordinates, reference_integrator, reference_dt, check_dt, T,
//                   reference_difference, reference_error_estimate
//   kind=ladder:    case coordinates, dt, steps, T, error, wall_per_sim_s, force_evals, status...
//   kind=fit:       case coordinates, order, r_squared, fit_dt_min, fit_dt_max, fit_points, note
// `cases` are expand_cases(spec) (no dt axis). Throws SweepError when T is not a whole number of
// every ladder step, or when the reference itself fails.
WorkPrecisionSummary run_work_precision(const SweepSpec& spec, const std::vector<CaseSpec>& cases,
                                        const TrajectoryRunner& runner, ResultsStore& store,
                                        Progress* progress);

// The converged reference for `base`'s problem: the reference integrator (or the case's own,
// when self-referenced) in float64 at dt and at dt / 2 to T = base's duration. Stores the
// reference row (reference_difference between the two, and its error estimate) unless stored;
// returns the finer run. Throws SweepError when either run is not stable.
Trajectory compute_reference(const SweepSpec& spec, const CaseSpec& base, double dt,
                             const TrajectoryRunner& runner, ResultsStore& store);

// What base's precision alone costs on this problem: the reference integrator at the reference's
// own step (dt / 2 of compute_reference's dt) in base's precision, against `reference` (that
// run in float64), as RMS distance over the diagonal. No integrator at any step can be expected
// below it: on the windy flag it holds float32 runs above a tolerance that float64 runs meet.
// Stores the precision_floor row (problem coordinates, precision, reference_integrator, dt, T,
// precision_floor) unless stored; returns 0 without a run when base is float64. Throws SweepError
// when the run is not stable.
double compute_precision_floor(const SweepSpec& spec, const CaseSpec& base, double dt,
                               const Trajectory& reference, const TrajectoryRunner& runner,
                               ResultsStore& store);

// Throws SweepError, naming where the setting was made, for a case given steps instead of a
// duration or whose duration is not a whole number of steps of every ladder dt and both
// reference dts. The driver checks this before it opens the results store, so bad input
// leaves no store behind; run_work_precision checks it again before it runs anything.
void check_work_precision_cases(const SweepSpec& spec, const std::vector<CaseSpec>& cases);

// Units of work run_work_precision performs (for a Progress total).
std::size_t work_precision_units(const SweepSpec& spec, const std::vector<CaseSpec>& cases);

}  // namespace clothlab::sweep
