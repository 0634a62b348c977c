#include "clothlab/analysis/stability_region.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace clothlab::analysis {
namespace {

constexpr double kModeOmega = 40.0;  // rad/s
const DampedMode kUndampedMode{kModeOmega * kModeOmega, 0.0};

TEST(StabilityRegion, UndampedOscillatorLimitsMatchTheory) {
  EXPECT_NEAR(predicted_dt_max(Method::SymplecticEuler, kUndampedMode) * kModeOmega, 2.0, 1e-6);
  EXPECT_NEAR(predicted_dt_max(Method::PositionVerlet, kUndampedMode) * kModeOmega, 2.0, 1e-6);
  EXPECT_NEAR(predicted_dt_max(Method::RungeKutta4, kUndampedMode) * kModeOmega,
              2.0 * std::sqrt(2.0), 1e-6);
  // Forward Euler grows at any step; midpoint grows by 1 + (w dt)^4 / 8 per step.
  EXPECT_EQ(predicted_dt_max(Method::ExplicitEuler, kUndampedMode), 0.0);
  EXPECT_LT(predicted_dt_max(Method::Midpoint, kUndampedMode) * kModeOmega, 1e-2);
}

TEST(StabilityRegion, DampedOscillatorLimitsMatchClosedForms) {
  const double c = 6.0;
  const DampedMode mode{kModeOmega * kModeOmega, c};
  // Forward Euler: |1 + h lambda| <= 1 with Re lambda = -c/2, |lambda|^2 = w^2 -> h <= c / w^2.
  EXPECT_NEAR(predicted_dt_max(Method::ExplicitEuler, mode), c / (kModeOmega * kModeOmega), 1e-9);
  // Symplectic Euler: trace 2 - hc - h^2 w^2, det 1 - hc; Jury: h^2 w^2 + 2 h c <= 4.
  const double symplectic =
      (-c + std::sqrt(c * c + 4.0 * kModeOmega * kModeOmega)) / (kModeOmega * kModeOmega);
  EXPECT_NEAR(predicted_dt_max(Method::SymplecticEuler, mode), symplectic, 1e-9);
}

TEST(StabilityRegion, RealAxisIntervals) {
  const double rate = 500.0;
  EXPECT_NEAR(predicted_dt_max(Method::ExplicitEuler, std::complex<double>(-rate, 0.0)) * rate, 2.0,
              1e-8);
  EXPECT_NEAR(predicted_dt_max(Method::Midpoint, std::complex<double>(-rate, 0.0)) * rate, 2.0,
              1e-8);
  // RK4: 1 + z + z^2/2 + z^3/6 + z^4/24 = 1 at z = -2.785293563405...
  EXPECT_NEAR(predicted_dt_max(Method::RungeKutta4, std::complex<double>(-rate, 0.0)) * rate,
              2.7852935634, 1e-8);
}

TEST(StabilityRegion, VerletWithTheSeedsPerStepDampingWidensSlightly) {
  VerletDamping seed;
  seed.per_step_fraction = 0.005;
  // h^2 w^2 <= 2 (1 + d), d = 0.995.
  EXPECT_NEAR(predicted_dt_max(Method::PositionVerlet, kUndampedMode, seed) * kModeOmega,
              std::sqrt(2.0 * 1.995), 1e-6);
}

TEST(StabilityRegion, NoDynamicsIsNeverUnstable) {
  EXPECT_EQ(predicted_dt_max(Method::RungeKutta4, DampedMode{0.0, 0.0}),
            std::numeric_limits<double>::infinity());
}

TEST(StabilityRegion, NonRungeKuttaMethodsHaveNoPolynomial) {
  EXPECT_THROW(stability_polynomial(Method::PositionVerlet, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab::analysis
