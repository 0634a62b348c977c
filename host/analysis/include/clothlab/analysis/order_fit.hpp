// Empirical order of accuracy: slope of log(error) against log(dt).
#pragma once

#include <cstddef>
#include <span>
#include <string>

namespace clothlab::analysis {

struct OrderFit {
  bool valid = false;
  double slope = 0.0;      // empirical order
  double intercept = 0.0;  // log(error) at log(dt) = 0
  double r_squared = 0.0;
  double dt_min = 0.0;  // range used, inclusive
  double dt_max = 0.0;
  std::size_t points = 0;  // points inside the range
  std::string note;        // why the fit is invalid, or which points were dropped
};

// Least squares over every point given (dt > 0, error > 0, both finite; others skipped).
OrderFit fit_order_all(std::span<const double> dt, std::span<const double> error);

struct OrderFitOptions {
  std::size_t min_points = 3;
  // A local slope (between neighbouring dt) belongs to the asymptotic range when it is within
  // max(absolute_tolerance, relative_tolerance * slope) of the range's fitted slope.
  double absolute_tolerance = 0.3;
  double relative_tolerance = 0.15;
};

// Chooses the asymptotic range automatically: the longest run of neighbouring points whose local
// slopes agree with the run's fitted slope (ties: best r^2). Points at the round-off floor
// (error no longer falling with dt) and pre-asymptotic points at large dt break that agreement
// and fall outside. Input order is free; points are sorted by dt.
OrderFit fit_order(std::span<const double> dt, std::span<const double> error,
                   const OrderFitOptions& options = {});

}  // namespace clothlab::analysis
