#include "order_fit.hpp"

#include <cmath>
#include <stdexcept>

namespace clothlab::conformance {

double observed_order(const std::vector<ErrorSample>& samples) {
  if (samples.size() < 2) throw std::invalid_argument("observed_order: needs two or more samples");
  double mean_x = 0, mean_y = 0;
  for (const ErrorSample& sample : samples) {
    if (!(sample.dt > 0) || !(sample.error > 0))
      throw std::invalid_argument("observed_order: dt and error must be positive");
    mean_x += std::log(sample.dt);
    mean_y += std::log(sample.error);
  }
  mean_x /= static_cast<double>(samples.size());
  mean_y /= static_cast<double>(samples.size());
  double covariance = 0, variance = 0;
  for (const ErrorSample& sample : samples) {
    const double dx = std::log(sample.dt) - mean_x;
    covariance += dx * (std::log(sample.error) - mean_y);
    variance += dx * dx;
  }
  if (variance == 0) throw std::invalid_argument("observed_order: all dt are equal");
  return covariance / variance;
}

}  // namespace clothlab::conformance
