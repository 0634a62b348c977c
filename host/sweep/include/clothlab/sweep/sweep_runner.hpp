// Runs the cases of a sweep through a callback, storing one row per case as it finishes.
#pragma once

#include <cstddef>
#include <functional>

#include "clothlab/sweep/case_result.hpp"
#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/progress.hpp"
#include "clothlab/sweep/results_store.hpp"

namespace clothlab::sweep {

using CaseRunner = std::function<CaseResult(const CaseSpec&)>;

struct SweepSummary {
  std::size_t total = 0;
  std::size_t skipped = 0;  // already in the results (resume)
  std::size_t stable = 0, unstable = 0, failed = 0;
  double wall_s = 0.0;
};

// The row stored for a case: key, coordinates, status, fail step/check/reason, metrics, notes.
Row case_row(const CaseSpec& spec, const CaseResult& result);

// Runs every case whose key is not yet in the store. An exception from the runner becomes a
// Failed row carrying its message (attempt_case); the sweep goes on. progress may be null.
SweepSummary run_sweep(const std::vector<CaseSpec>& cases, const CaseRunner& runner,
                       ResultsStore& store, Progress* progress);

// A one-line label for progress output: "rk4 flag 50x50 dt=0.001".
std::string case_label(const CaseSpec& spec);

}  // namespace clothlab::sweep
