#include "analytic.hpp"

#include <gtest/gtest.h>

#include <cmath>

using namespace clothlab::conformance;

TEST(DampedOscillator, StartsAtTheInitialState) {
  const Oscillation start = damped_oscillator(10.0, 1.0, 1.0, 0.1, -0.3, 0.0);
  EXPECT_DOUBLE_EQ(start.position, 0.1);
  EXPECT_NEAR(start.velocity, -0.3, 1e-15);
}

TEST(DampedOscillator, UndampedIsACosineByHand) {
  // k = 4, m = 1: omega = 2; at t = pi/4 the cosine is at zero and u' = -u0 omega.
  const Oscillation quarter = damped_oscillator(4.0, 0.0, 1.0, 0.1, 0.0, M_PI / 4);
  EXPECT_NEAR(quarter.position, 0.0, 1e-15);
  EXPECT_NEAR(quarter.velocity, -0.2, 1e-15);
}

TEST(DampedOscillator, DecaysByTheEnvelopeAfterAFullDampedPeriod) {
  // k = 10, c = 1, m = 1: gamma = 1/2, omega_d = sqrt(9.75); after one period 2 pi / omega_d
  // the phase is back and the amplitude is u0 exp(-gamma T); u' = -gamma u + B omega_d e.
  const double period = 2 * M_PI / std::sqrt(9.75);
  const Oscillation later = damped_oscillator(10.0, 1.0, 1.0, 0.1, 0.0, period);
  EXPECT_NEAR(later.position, 0.1 * std::exp(-0.5 * period), 1e-14);
  EXPECT_NEAR(later.velocity, 0.0, 1e-14);  // B omega_d - gamma A = v0 = 0
}

TEST(FreeFall, IsTheQuadraticByHand) {
  const Motion motion = free_fall({0, 1, 0}, {1, 2, 0}, {0, -10, 0}, 2.0);
  EXPECT_DOUBLE_EQ(motion.position[0], 2.0);
  EXPECT_DOUBLE_EQ(motion.position[1], 1.0 + 4.0 - 20.0);
  EXPECT_DOUBLE_EQ(motion.velocity[1], 2.0 - 20.0);
}
