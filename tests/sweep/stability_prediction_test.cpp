// The prediction through the real core on a scene whose spectrum is known by hand: two
// particles, the top one pinned, one structural spring; the free particle carries half the mass.
#include "clothlab/analysis/stability_prediction.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace clothlab::analysis {
namespace {

constexpr double kSpringStiffness = 80.0, kSpringDamping = 0.05, kPairMass = 0.1;

Scene single_spring(double damping) {
  Scene scene;
  scene.rows = 2;
  scene.cols = 1;
  scene.height = 0.4;
  scene.total_mass = kPairMass;
  scene.structural = {kSpringStiffness, damping};
  scene.pinned = {0};
  return scene;
}

TEST(StabilityPrediction, UndampedSpringThroughTheCore) {
  const double omega = std::sqrt(kSpringStiffness / (kPairMass / 2.0));
  const StabilityPrediction verlet = predict_stability(single_spring(0.0), Method::PositionVerlet);
  EXPECT_NEAR(verlet.spectrum.omega_max, omega, 1e-5 * omega);
  EXPECT_NEAR(verlet.dt_max * omega, 2.0, 1e-4);
  const StabilityPrediction rk4 = predict_stability(single_spring(0.0), Method::RungeKutta4);
  EXPECT_NEAR(rk4.dt_max * omega, 2.0 * std::sqrt(2.0), 1e-3);
}

TEST(StabilityPrediction, DampedSpringThroughTheCore) {
  const double omega2 = kSpringStiffness / (kPairMass / 2.0);
  const double c = kSpringDamping / (kPairMass / 2.0);
  const StabilityPrediction euler =
      predict_stability(single_spring(kSpringDamping), Method::ExplicitEuler);
  EXPECT_NEAR(euler.spectrum.stiffest_mode.damping_rate, c, 1e-5 * c);
  EXPECT_NEAR(euler.dt_max, c / omega2, 1e-4 * c / omega2);
  const StabilityPrediction symplectic =
      predict_stability(single_spring(kSpringDamping), Method::SymplecticEuler);
  const double expected = (-c + std::sqrt(c * c + 4.0 * omega2)) / omega2;
  EXPECT_NEAR(symplectic.dt_max, expected, 1e-4 * expected);
}

}  // namespace
}  // namespace clothlab::analysis
