// What one case produced. A divergence is a result (Unstable), an exception is a result
// (Failed): neither stops the sweep.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace clothlab::sweep {

enum class CaseStatus { Stable, Unstable, Failed };
const char* to_string(CaseStatus status);

struct CaseResult {
  CaseStatus status = CaseStatus::Stable;
  uint64_t fail_step = 0;  // Unstable: the step at which the verdict fired
  std::string check;       // Unstable: which check fired ("stretch", "energy", "non-finite")
  std::string reason;      // Unstable / Failed: one line
  // Measurements in the order they should appear as columns: ms_per_step, force_evals, ...
  std::vector<std::pair<std::string, double>> metrics;
  std::vector<std::pair<std::string, std::string>> notes;  // text columns
  bool stable() const { return status == CaseStatus::Stable; }
};

}  // namespace clothlab::sweep
