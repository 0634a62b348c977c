// A single damped spring written directly against the C ABI: particle 0 pinned at the origin,
// particle 1 free at (L, 0, 0), so the only non-zero mode has w^2 = k/m and damping c = kd/m.
#include "clothlab/analysis/spectral_estimate.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace clothlab::analysis {
namespace {

constexpr uint32_t kStride = 16;
constexpr double kRest = 0.5, kStiffness = 200.0, kDampingCoefficient = 0.6, kMass = 0.02;

struct SingleSpring {
  alignas(64) std::array<double, 3 * kStride> x{};
  alignas(64) std::array<double, 3 * kStride> v{};
  std::array<double, 2> inverse_mass{0.0, 1.0 / kMass};
  clothlab_range active{1, 2};
  double damping_coefficient;  // kd, N s/m
  clothlab_system system{};

  explicit SingleSpring(double kd = kDampingCoefficient) : damping_coefficient(kd) {
    x[1] = kRest;
    system.struct_size = sizeof(clothlab_system);
    system.precision = CLOTHLAB_FLOAT64;
    system.particle_count = 2;
    system.stride = kStride;
    system.x = x.data();
    system.v = v.data();
    system.inverse_mass = inverse_mass.data();
    system.active = &active;
    system.active_count = 1;
    system.context = &damping_coefficient;
    system.eval_acceleration = &acceleration;
  }

  // Hooke + damping along the spring + gravity (which the linearisation must cancel).
  static clothlab_status acceleration(void* context, double, const void* xp, const void* vp,
                                      void* ap) {
    const double kd = *static_cast<const double*>(context);
    const auto* x = static_cast<const double*>(xp);
    const auto* v = static_cast<const double*>(vp);
    auto* a = static_cast<double*>(ap);
    double d[3], length = 0.0;
    for (int k = 0; k < 3; ++k) {
      d[k] = x[k * kStride + 1] - x[k * kStride];
      length += d[k] * d[k];
    }
    length = std::sqrt(length);
    double closing = 0.0;
    for (int k = 0; k < 3; ++k) closing += (v[k * kStride + 1] - v[k * kStride]) * d[k] / length;
    const double tension = kStiffness * (length - kRest) + kd * closing;
    for (int k = 0; k < 3; ++k) {
      a[k * kStride] = 0.0;
      a[k * kStride + 1] = -tension * d[k] / length / kMass + (k == 1 ? -9.81 : 0.0);
    }
    return CLOTHLAB_OK;
  }
};

TEST(SpectralEstimate, SingleSpringFrequencyIsSqrtKOverM) {
  SingleSpring spring;
  const SpectralEstimate estimate = estimate_spectrum(spring.system, 0.0);
  const double omega = std::sqrt(kStiffness / kMass);
  const double c = kDampingCoefficient / kMass;
  EXPECT_TRUE(estimate.power_iterations_converged);
  EXPECT_NEAR(estimate.omega_max, omega, 1e-5 * omega);
  EXPECT_NEAR(estimate.stiffest_mode.damping_rate, c, 1e-6 * c);
  EXPECT_NEAR(estimate.most_damped_mode.damping_rate, c, 1e-6 * c);
  EXPECT_NEAR(estimate.most_damped_mode.omega_squared, omega * omega, 1e-5 * omega * omega);
  // Damped first-order system: s^2 + c s + w^2 = 0.
  EXPECT_NEAR(estimate.dominant_eigenvalue.real(), -c / 2.0, 1e-4 * omega);
  EXPECT_NEAR(std::abs(estimate.dominant_eigenvalue.imag()), std::sqrt(omega * omega - c * c / 4.0),
              1e-4 * omega);
  // The state is left as it was.
  EXPECT_EQ(spring.x[1], kRest);
  EXPECT_EQ(spring.v[1], 0.0);
}

TEST(SpectralEstimate, PredictedDtMaxOnTheSpringMatchesTheory) {
  SingleSpring spring;
  const SpectralEstimate estimate = estimate_spectrum(spring.system, 0.0);
  const double omega2 = kStiffness / kMass;
  const double c = kDampingCoefficient / kMass;
  EXPECT_NEAR(predict_dt_max(Method::PositionVerlet, estimate), 2.0 / std::sqrt(omega2),
              1e-5 / std::sqrt(omega2));
  EXPECT_NEAR(predict_dt_max(Method::ExplicitEuler, estimate), c / omega2, 1e-4 * c / omega2);
  const double symplectic = (-c + std::sqrt(c * c + 4.0 * omega2)) / omega2;
  EXPECT_NEAR(predict_dt_max(Method::SymplecticEuler, estimate), symplectic, 1e-4 * symplectic);
}

// Overdamped (c^2 > 4 w^2): the first-order system's outer eigenvalue is real, and the mode
// behind it keeps its slow root. Symplectic Euler (one-stage table) is stable while
// h^2 w^2 + 2 h c <= 4; read as a double root, the fast root alone gives about half that h.
TEST(SpectralEstimate, AnOverdampedModeKeepsBothRootsInTheTablesPrediction) {
  constexpr double kHeavyDamping = 10.0;
  SingleSpring spring(kHeavyDamping);
  const SpectralEstimate estimate = estimate_spectrum(spring.system, 0.0);
  const double omega2 = kStiffness / kMass;
  const double c = kHeavyDamping / kMass;
  ASSERT_GT(c * c, 4.0 * omega2);
  EXPECT_NEAR(estimate.dominant_eigenvalue.real(), -c / 2.0 - std::sqrt(c * c / 4.0 - omega2),
              1e-6 * c);
  ASSERT_EQ(estimate.outer_modes.size(), estimate.outer_eigenvalues.size());
  ASSERT_FALSE(estimate.outer_modes.empty());
  EXPECT_NEAR(estimate.outer_modes.front().omega_squared, omega2, 1e-6 * omega2);
  EXPECT_NEAR(estimate.outer_modes.front().damping_rate, c, 1e-6 * c);

  RknTable symplectic_euler;
  symplectic_euler.stages = 1;
  symplectic_euler.c = symplectic_euler.alpha = {0.0};
  symplectic_euler.x_coupling = symplectic_euler.v_coupling = {0.0};
  symplectic_euler.x_weights = symplectic_euler.v_weights = {1.0};
  const double expected = (-c + std::sqrt(c * c + 4.0 * omega2)) / omega2;
  EXPECT_NEAR(predict_dt_max(symplectic_euler, estimate, true), expected, 1e-3 * expected);
}

TEST(SpectralEstimate, RejectsFloat32Systems) {
  SingleSpring spring;
  spring.system.precision = CLOTHLAB_FLOAT32;
  EXPECT_THROW(estimate_spectrum(spring.system, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab::analysis
