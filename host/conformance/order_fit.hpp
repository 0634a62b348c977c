// Observed order of accuracy from errors at a sequence of step sizes.
#pragma once

#include <vector>

namespace clothlab::conformance {

struct ErrorSample {
  double dt;
  double error;
};

// Least-squares slope of log(error) against log(dt). Needs two or more samples with
// positive dt and error; throws std::invalid_argument otherwise.
double observed_order(const std::vector<ErrorSample>& samples);

}  // namespace clothlab::conformance
