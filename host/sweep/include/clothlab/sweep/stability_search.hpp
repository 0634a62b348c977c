// Stability mode: per case, the largest stable dt (bracket + bisect on real runs) beside the
// dt_max predicted from the linearised system.
#pragma once

#include <complex>
#include <functional>
#include <optional>

#include "clothlab/sweep/sweep_runner.hpp"

namespace clothlab::sweep {

struct DtPrediction {
  double dt_max = 0.0;     // s
  double omega_max = 0.0;  // rad/s, stiffness part
  std::complex<double> dominant_eigenvalue;
};
// Estimates dt_max for the case (integrator, scene, parameters); may throw.
using DtPredictor = std::function<DtPrediction(const CaseSpec&)>;

struct StabilitySummary {
  std::size_t searched = 0, skipped = 0;
};

// For each case (no dt axis): the predictor, if given, runs first and its dt_max (clamped to the
// search limits) is the first probe; then find_max_dt probes runner(with_dt(case, dt)), stable
// when the result is Stable. A probe that throws or fails counts as unstable and its reason is
// kept. Row (key "stability;<case key>"): coordinates, dt_max (largest stable), dt_unstable,
// outcome, evaluations, predicted_dt_max, omega_max, dominant_re, dominant_im,
// measured_over_predicted, check and reason of the failure at dt_unstable.
StabilitySummary run_stability_search(const SweepSpec& spec, const std::vector<CaseSpec>& cases,
                                      const CaseRunner& runner, const DtPredictor& predictor,
                                      ResultsStore& store, Progress* progress);

}  // namespace clothlab::sweep
