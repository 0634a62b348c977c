#include "clothlab/sweep/sweep_runner.hpp"

#include <chrono>

#include "clothlab/sweep/case_attempt.hpp"

namespace clothlab::sweep {

Row case_row(const CaseSpec& spec, const CaseResult& result) {
  Row row;
  row["key"] = spec.key;
  for (const auto& [name, value] : spec.coordinates) row[name] = value;
  row["status"] = to_string(result.status);
  row["stable"] = result.stable();
  row["fail_step"] = result.status == CaseStatus::Unstable ? Row(result.fail_step) : Row();
  row["check"] = result.check;
  row["reason"] = result.reason;
  for (const auto& [name, value] : result.metrics) row[name] = value;
  for (const auto& [name, value] : result.notes) row[name] = value;
  return row;
}

std::string case_label(const CaseSpec& spec) {
  std::string label;
  for (const auto& [name, value] : spec.coordinates) {
    const bool bare =
        name == "integrator" || name == "scenario" || name == "mesh" || name == "precision";
    label += (label.empty() ? "" : " ") + (bare ? value : name + "=" + value);
  }
  return label;
}

SweepSummary run_sweep(const std::vector<CaseSpec>& cases, const CaseRunner& runner,
                       ResultsStore& store, Progress* progress) {
  const auto start = std::chrono::steady_clock::now();
  SweepSummary summary;
  summary.total = cases.size();
  for (const CaseSpec& spec : cases) {
    if (store.contains(spec.key)) {
      ++summary.skipped;
      continue;
    }
    const CaseResult result = attempt_case(runner, spec);
    switch (result.status) {
      case CaseStatus::Stable:
        ++summary.stable;
        break;
      case CaseStatus::Unstable:
        ++summary.unstable;
        break;
      case CaseStatus::Failed:
        ++summary.failed;
        break;
    }
    store.append(case_row(spec, result), spec.index);
    if (progress) progress->case_finished(case_label(spec));
  }
  if (progress) progress->finish();
  summary.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace clothlab::sweep
