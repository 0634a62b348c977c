// One step of each integrator on a two-particle system, against values worked out by hand.
//
// Particle 0 is pinned at the origin; particle 1 hangs below it on a spring of rest length
// 1 along y. Per unit mass: stiffness 100 1/s^2, damping 2 1/s, gravity 10 m/s^2:
//   a(y, v) = 100 (y0 - y - 1) - 2 (v - v0) - 10 = -100 y - 110 - 2 v    (y0 = v0 = 0),
// the damping term only when the integrator asks for velocity-dependent forces.
// Start: y = -1.2, v = 0.5; step dt = 0.1.
#include <gtest/gtest.h>

#include <cmath>

#include "integrator_harness.hpp"

namespace clothlab::test {
namespace {

constexpr double dt = 0.1;
constexpr double tolerance = 1e-12;

Vec3 hanging_spring(double, uint32_t i, const double* x, const double* v, uint32_t stride) {
  const double y = x[stride + i], y0 = x[stride + 0];
  double a = 100.0 * (y0 - y - 1.0) - 10.0;
  if (v != nullptr) a -= 2.0 * (v[stride + i] - v[stride + 0]);
  return {0.0, a, 0.0};
}

struct TwoParticles {
  TwoParticles() : system(2, {0}, hanging_spring) {
    system.set_position(1, {0.0, -1.2, 0.0});
    system.set_velocity(1, {0.0, 0.5, 0.0});
  }
  void expect_state(double y, double v) const {
    EXPECT_NEAR(system.position(1)[1], y, tolerance);
    EXPECT_NEAR(system.velocity(1)[1], v, tolerance);
    for (int k : {0, 2}) {
      EXPECT_EQ(system.position(1)[k], 0.0);
      EXPECT_EQ(system.velocity(1)[k], 0.0);
    }
    EXPECT_EQ(system.position(0), (Vec3{0, 0, 0}));
    EXPECT_EQ(system.velocity(0), (Vec3{0, 0, 0}));
  }
  MockSystem<double> system;
};

TEST(IntegratorOneStep, SemiImplicitEulerUsesTheNewVelocityForThePosition) {
  // a = 120 - 110 - 1 = 9;  v = 0.5 + 0.1 * 9 = 1.4;  y = -1.2 + 0.1 * 1.4 = -1.06
  TwoParticles s;
  Integrator euler("euler");
  euler.start(s.system);
  euler.run(s.system, 1, dt);
  s.expect_state(-1.06, 1.4);
}

TEST(IntegratorOneStep, MidpointMatchesHandValues) {
  // a1 = 9;  y_mid = -1.2 + 0.05 * 0.5 = -1.175;  v_mid = 0.5 + 0.05 * 9 = 0.95
  // a2 = 117.5 - 110 - 1.9 = 5.6
  // y = -1.2 + 0.1 * 0.95 = -1.105;  v = 0.5 + 0.1 * 5.6 = 1.06
  TwoParticles s;
  Integrator midpoint("midpoint");
  midpoint.start(s.system);
  midpoint.run(s.system, 1, dt);
  s.expect_state(-1.105, 1.06);
}

TEST(IntegratorOneStep, Rk4MatchesHandValues) {
  // k1: v1 = 0.5,                          a1 = 9
  // k2: y2 = -1.175,  v2 = 0.95,           a2 = 117.5 - 110 - 1.9 = 5.6
  // k3: y3 = -1.2 + 0.05 * 0.95 = -1.1525,  v3 = 0.5 + 0.05 * 5.6 = 0.78
  //                                         a3 = 115.25 - 110 - 1.56 = 3.69
  // k4: y4 = -1.2 + 0.1 * 0.78 = -1.122,    v4 = 0.5 + 0.1 * 3.69 = 0.869
  //                                         a4 = 112.2 - 110 - 1.738 = 0.462
  // y = -1.2 + 0.1/6 (0.5 + 1.9 + 1.56 + 0.869) = -1.2 + 4.829 / 60
  // v = 0.5 + 0.1/6 (9 + 11.2 + 7.38 + 0.462)   =  0.5 + 28.042 / 60
  TwoParticles s;
  Integrator rk4("rk4");
  rk4.start(s.system);
  rk4.run(s.system, 1, dt);
  s.expect_state(-1.2 + 4.829 / 60.0, 0.5 + 28.042 / 60.0);
}

TEST(IntegratorOneStep, VerletWithoutDampingMatchesHandValues) {
  // No velocities reach the force law: a(y) = -100 y - 110.
  // Step 1 (no history): a0 = 10;  d0 = dt v0 + dt^2/2 a0 = 0.05 + 0.05 = 0.1
  //                      y1 = -1.1;  v1 = d0/dt + dt/2 a0 = 1 + 0.5 = 1.5
  // Step 2: a1 = 110 - 110 = 0;  d1 = d0 + dt^2 a1 = 0.1;  y2 = -1.0;  v2 = d1/dt = 1.0
  TwoParticles s;
  Integrator verlet("verlet");
  verlet.with("damping", 0.0).start(s.system);
  verlet.run(s.system, 1, dt);
  s.expect_state(-1.1, 1.5);
  ASSERT_EQ(verlet.step(s.system, dt, dt), CLOTHLAB_OK) << verlet.message();
  s.expect_state(-1.0, 1.0);
}

TEST(IntegratorOneStep, VerletWithSeedDampingPerStepMatchesHandValues) {
  // damping_per_step p = 0.5: f = 0.5, beta = dt^2 (seed eq. 2.19); start and velocity use
  // the equivalent drag z = c dt = -ln(1 - p) = ln 2, for which
  //   w = (1 - e^{-z}) / z = 0.5 / ln 2,   1 / phi = z / (e^z - 1) = ln 2.
  // Step 1: a0 = 10, v0 = 0.5
  //   d0 = dt w v0 + dt^2 (1 - w) / z a0 = 0.025 / ln 2 + 0.1 (1 - 0.5 / ln 2) / ln 2
  //   v1 = d0 / (dt phi) + dt (1 - 1 / phi) / z a0 = 10 ln 2 d0 + (1 - ln 2) / ln 2
  // Step 2: a1 = -100 y1 - 110;  d1 = 0.5 d0 + 0.01 a1
  //   v2 = 10 ln 2 d1 + 0.1 (1 - ln 2) / ln 2 a1
  const double ln2 = std::log(2.0);
  TwoParticles s;
  Integrator verlet("verlet");
  verlet.with("damping_per_step", 0.5).start(s.system);
  verlet.run(s.system, 1, dt);
  const double d0 = 0.025 / ln2 + 0.1 * (1.0 - 0.5 / ln2) / ln2;
  const double y1 = -1.2 + d0;
  s.expect_state(y1, 10.0 * ln2 * d0 + (1.0 - ln2) / ln2);
  ASSERT_EQ(verlet.step(s.system, dt, dt), CLOTHLAB_OK) << verlet.message();
  const double a1 = -100.0 * y1 - 110.0, d1 = 0.5 * d0 + 0.01 * a1;
  s.expect_state(y1 + d1, 10.0 * ln2 * d1 + 0.1 * (1.0 - ln2) / ln2 * a1);
}

}  // namespace
}  // namespace clothlab::test
