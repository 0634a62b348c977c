// Human, JSON and JUnit forms of a conformance run's results.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runner.hpp"

namespace clothlab::conformance {

struct RunReport {
  uint64_t seed = 0;
  double timeout_s = 0;
  std::vector<CheckResult> results;

  size_t passed() const;
  size_t failed() const;
};

// "PASS rk4:rk4 numerics.order-spring — measured order 4.01, declared 4 (...)"
std::string result_line(const CheckResult& result);
// "N passed, N failed"
std::string summary_line(const RunReport& report);

std::string to_json(const RunReport& report);
std::string to_junit(const RunReport& report);

}  // namespace clothlab::conformance
