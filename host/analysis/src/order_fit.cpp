#include "clothlab/analysis/order_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace clothlab::analysis {
namespace {

struct LogPoint {
  double log_dt;
  double log_error;
};

std::vector<LogPoint> usable_points(std::span<const double> dt, std::span<const double> error) {
  if (dt.size() != error.size()) {
    throw std::invalid_argument("order fit: " + std::to_string(dt.size()) + " dt values but " +
                                std::to_string(error.size()) + " errors");
  }
  std::vector<LogPoint> points;
  for (std::size_t i = 0; i < dt.size(); ++i) {
    if (std::isfinite(dt[i]) && std::isfinite(error[i]) && dt[i] > 0.0 && error[i] > 0.0) {
      points.push_back({std::log(dt[i]), std::log(error[i])});
    }
  }
  std::sort(points.begin(), points.end(),
            [](const LogPoint& a, const LogPoint& b) { return a.log_dt < b.log_dt; });
  return points;
}

OrderFit least_squares(const std::vector<LogPoint>& points, std::size_t first, std::size_t last) {
  OrderFit fit;
  fit.points = last - first + 1;
  fit.dt_min = std::exp(points[first].log_dt);
  fit.dt_max = std::exp(points[last].log_dt);
  if (fit.points < 2) {
    fit.note = "fewer than 2 usable points";
    return fit;
  }
  const double count = static_cast<double>(fit.points);
  double mean_x = 0.0, mean_y = 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    mean_x += points[i].log_dt;
    mean_y += points[i].log_error;
  }
  mean_x /= count;
  mean_y /= count;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = first; i <= last; ++i) {
    const double dx = points[i].log_dt - mean_x;
    const double dy = points[i].log_error - mean_y;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (sxx <= 0.0) {
    fit.note = "all dt values are equal";
    return fit;
  }
  fit.valid = true;
  fit.slope = sxy / sxx;
  fit.intercept = mean_y - fit.slope * mean_x;
  fit.r_squared = syy > 0.0 ? (sxy * sxy) / (sxx * syy) : 1.0;
  return fit;
}

double local_slope(const std::vector<LogPoint>& points, std::size_t i) {
  return (points[i + 1].log_error - points[i].log_error) /
         (points[i + 1].log_dt - points[i].log_dt);
}

bool slopes_agree(const std::vector<LogPoint>& points, std::size_t first, std::size_t last,
                  double slope, const OrderFitOptions& options) {
  const double tolerance =
      std::max(options.absolute_tolerance, options.relative_tolerance * std::abs(slope));
  for (std::size_t i = first; i < last; ++i) {
    if (std::abs(local_slope(points, i) - slope) > tolerance) return false;
  }
  return true;
}

}  // namespace

OrderFit fit_order_all(std::span<const double> dt, std::span<const double> error) {
  const auto points = usable_points(dt, error);
  if (points.size() < 2) {
    OrderFit fit;
    fit.note = "fewer than 2 usable points";
    return fit;
  }
  return least_squares(points, 0, points.size() - 1);
}

OrderFit fit_order(std::span<const double> dt, std::span<const double> error,
                   const OrderFitOptions& options) {
  const auto points = usable_points(dt, error);
  const std::size_t min_points = std::max<std::size_t>(options.min_points, 2);
  OrderFit best;
  best.note = "no run of " + std::to_string(min_points) +
              " neighbouring points with a consistent slope (" + std::to_string(points.size()) +
              " usable points)";
  for (std::size_t first = 0; first < points.size(); ++first) {
    for (std::size_t last = first + min_points - 1; last < points.size(); ++last) {
      OrderFit fit = least_squares(points, first, last);
      if (!fit.valid || fit.slope <= 0.0 ||
          !slopes_agree(points, first, last, fit.slope, options)) {
        continue;
      }
      const bool longer = fit.points > best.points;
      const bool as_long_but_tighter = fit.points == best.points && fit.r_squared > best.r_squared;
      if (!best.valid || longer || as_long_but_tighter) best = fit;
    }
  }
  if (best.valid && best.points < points.size()) {
    best.note = std::to_string(points.size() - best.points) + " of " +
                std::to_string(points.size()) + " points outside the asymptotic range";
  }
  return best;
}

}  // namespace clothlab::analysis
