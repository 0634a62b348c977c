#include "clothlab/sweep/stability_search.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "clothlab/sweep/case_attempt.hpp"

namespace clothlab::sweep {

StabilitySummary run_stability_search(const SweepSpec& spec, const std::vector<CaseSpec>& cases,
                                      const CaseRunner& runner, const DtPredictor& predictor,
                                      ResultsStore& store, Progress* progress) {
  StabilitySummary summary;
  for (const CaseSpec& c : cases) {
    const std::string key = "stability;" + c.key;
    if (store.contains(key)) {
      ++summary.skipped;
      continue;
    }
    Row row;
    row["key"] = key;
    row["kind"] = "stability";
    for (const auto& [name, value] : c.coordinates) row[name] = value;

    analysis::MaxDtOptions options = spec.stability;
    row["predicted_dt_max"] = nullptr;
    if (predictor) {
      try {
        const DtPrediction prediction = predictor(c);
        row["predicted_dt_max"] = prediction.dt_max;
        row["omega_max"] = prediction.omega_max;
        row["dominant_re"] = prediction.dominant_eigenvalue.real();
        row["dominant_im"] = prediction.dominant_eigenvalue.imag();
        if (prediction.dt_max > 0.0 && std::isfinite(prediction.dt_max)) {
          options.dt_initial =
              std::clamp(prediction.dt_max, options.dt_lower_limit, options.dt_upper_limit);
        }
      } catch (const std::exception& error) {
        row["prediction_error"] = error.what();
      }
    }

    CaseResult first_failure;  // the probe at the smallest unstable dt
    double failure_dt = 0.0;
    const analysis::MaxDtResult result = analysis::find_max_dt(
        [&](double dt) {
          const CaseResult probe = attempt_case(runner, with_dt(c, dt));
          if (!probe.stable() && (failure_dt == 0.0 || dt < failure_dt)) {
            failure_dt = dt;
            first_failure = probe;
          }
          return probe.stable();
        },
        options);
    row["dt_max"] = result.dt_stable;
    row["dt_unstable"] = result.dt_unstable > 0.0 ? Row(result.dt_unstable) : Row();
    row["outcome"] = analysis::to_string(result.outcome);
    row["evaluations"] = result.evaluations;
    const bool comparable = row["predicted_dt_max"].is_number() && result.dt_stable > 0.0 &&
                            row["predicted_dt_max"].get<double>() > 0.0;
    row["measured_over_predicted"] =
        comparable ? Row(result.dt_stable / row["predicted_dt_max"].get<double>()) : Row();
    row["check"] = first_failure.check;
    row["fail_status"] = failure_dt > 0.0 ? to_string(first_failure.status) : "";
    row["reason"] = first_failure.reason;
    store.append(row, c.index);
    ++summary.searched;
    if (progress) progress->case_finished(case_label(c));
  }
  if (progress) progress->finish();
  return summary;
}

}  // namespace clothlab::sweep
