#include "statistics.hpp"

#include <algorithm>
#include <cmath>

namespace clothlab::cli {

double quantile(std::vector<double> sample, double q) {
  if (sample.empty()) return 0.0;
  std::sort(sample.begin(), sample.end());
  const double position = q * static_cast<double>(sample.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(position));
  const size_t above = std::min(below + 1, sample.size() - 1);
  const double fraction = position - static_cast<double>(below);
  return sample[below] + fraction * (sample[above] - sample[below]);
}

}  // namespace clothlab::cli
