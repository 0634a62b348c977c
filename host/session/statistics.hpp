// Order statistics of per-step timings.
#pragma once

#include <vector>

namespace clothlab::cli {

// The q-quantile (0 <= q <= 1) with linear interpolation between order statistics
// (Hyndman-Fan type 7, as numpy's default); 0 for an empty sample.
double quantile(std::vector<double> sample, double q);

}  // namespace clothlab::cli
