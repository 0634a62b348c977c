#include "clothlab/analysis/order_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace clothlab::analysis {
namespace {

// Global error at T = 1 of a Runge-Kutta method on y' = -y, y(0) = 1, with step h: the exact
// discrete solution is R(-h)^(1/h), so no integrator code is involved.
double rk_error(int order, double h) {
  const double z = -h;
  double amplification = 1.0, term = 1.0;
  for (int k = 1; k <= order; ++k) {
    term *= z / k;
    amplification += term;
  }
  const int steps = static_cast<int>(std::lround(1.0 / h));
  double y = 1.0;
  for (int i = 0; i < steps; ++i) y *= amplification;
  return std::abs(y - std::exp(-1.0));
}

TEST(OrderFit, ExactPowerLawGivesItsExponent) {
  const std::vector<double> dt = {0.1, 0.05, 0.025, 0.0125};
  std::vector<double> error;
  for (double h : dt) error.push_back(3.0 * std::pow(h, 2.0));
  const OrderFit fit = fit_order(dt, error);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.slope, 2.0, 1e-12);
  EXPECT_NEAR(fit.intercept, std::log(3.0), 1e-12);
  EXPECT_NEAR(fit.r_squared, 1.0, 1e-12);
  EXPECT_EQ(fit.points, 4u);
}

TEST(OrderFit, ForwardEulerOnDecayIsFirstOrder) {
  std::vector<double> dt, error;
  for (int k = 2; k <= 12; ++k) {
    dt.push_back(std::ldexp(1.0, -k));
    error.push_back(rk_error(1, dt.back()));
  }
  const OrderFit fit = fit_order(dt, error);
  ASSERT_TRUE(fit.valid) << fit.note;
  EXPECT_NEAR(fit.slope, 1.0, 0.05);
}

TEST(OrderFit, Rk4RangeExcludesTheRoundOffFloor) {
  // From h = 1/2 down to 2^-14: the error falls as h^4 until it meets round-off (~1e-16 per
  // step), then wanders; the fit must keep only the h^4 part.
  std::vector<double> dt, error;
  for (int k = 1; k <= 14; ++k) {
    dt.push_back(std::ldexp(1.0, -k));
    error.push_back(rk_error(4, dt.back()));
  }
  const OrderFit fit = fit_order(dt, error);
  ASSERT_TRUE(fit.valid) << fit.note;
  EXPECT_NEAR(fit.slope, 4.0, 0.15);
  EXPECT_GT(fit.dt_min, std::ldexp(1.0, -11));  // round-off dominates below ~2^-9
  EXPECT_LT(fit.points, dt.size());
  // Fitting every point would be badly wrong: the floor drags the slope down.
  EXPECT_LT(fit_order_all(dt, error).slope, 3.0);
}

TEST(OrderFit, DropsAPreAsymptoticPointAtLargeDt) {
  std::vector<double> dt = {0.8, 0.1, 0.05, 0.025, 0.0125};
  std::vector<double> error = {5.0, 1e-3, 2.5e-4, 6.25e-5, 1.5625e-5};
  const OrderFit fit = fit_order(dt, error);
  ASSERT_TRUE(fit.valid);
  EXPECT_NEAR(fit.slope, 2.0, 1e-9);
  EXPECT_DOUBLE_EQ(fit.dt_max, 0.1);
  EXPECT_EQ(fit.points, 4u);
}

TEST(OrderFit, TooFewPointsIsInvalidWithAReason) {
  const std::vector<double> dt = {0.1, 0.05};
  const std::vector<double> error = {1.0, 0.5};
  const OrderFit fit = fit_order(dt, error);
  EXPECT_FALSE(fit.valid);
  EXPECT_FALSE(fit.note.empty());
}

}  // namespace
}  // namespace clothlab::analysis
