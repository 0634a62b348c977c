// Free fall of a single particle, x(t) = start_position + start_velocity t - g t^2 / 2 along y.
// Midpoint, RK4 and Verlet integrate a constant acceleration exactly (up to round-off).
// Semi-implicit Euler moves with the end-of-step velocity, so after n steps
//   y_n = y0 + dt sum_{k=1..n} (start_velocity - g k dt) = y0 + start_velocity t - g t^2 / 2 - g t
//   dt / 2,
// an error of exactly -g t dt / 2: first order in dt.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "integrator_harness.hpp"

namespace clothlab::test {
namespace {

constexpr Vec3 start_position{1.0, 2.0, 3.0};
constexpr Vec3 start_velocity{0.5, 1.0, -0.25};
constexpr double round_off = 1e-12;

Vec3 gravity(double, uint32_t, const double*, const double*, uint32_t) { return {0.0, -g, 0.0}; }

struct FreeFall {
  FreeFall(const std::string& id, int steps, double dt) : integrator(id), system(1, {}, gravity) {
    system.set_position(0, start_position);
    system.set_velocity(0, start_velocity);
    if (id == "verlet") integrator.with("damping", 0.0);
    integrator.start(system);
    integrator.run(system, steps, dt);
  }
  Integrator integrator;
  MockSystem<double> system;
};

void expect_exact_velocity(const MockSystem<double>& system, double t) {
  EXPECT_NEAR(system.velocity(0)[0], start_velocity[0], round_off);
  EXPECT_NEAR(system.velocity(0)[1], start_velocity[1] - g * t, round_off);
  EXPECT_NEAR(system.velocity(0)[2], start_velocity[2], round_off);
}

class ExactFreeFall : public testing::TestWithParam<std::string> {};

TEST_P(ExactFreeFall, MatchesTheParabolaToRoundOff) {
  const int steps = 100;
  const double dt = 0.01, t = steps * dt;
  FreeFall fall(GetParam(), steps, dt);
  const Vec3 x = fall.system.position(0);
  EXPECT_NEAR(x[0], start_position[0] + start_velocity[0] * t, round_off);
  EXPECT_NEAR(x[1], start_position[1] + start_velocity[1] * t - 0.5 * g * t * t, round_off);
  EXPECT_NEAR(x[2], start_position[2] + start_velocity[2] * t, round_off);
  expect_exact_velocity(fall.system, t);
}

INSTANTIATE_TEST_SUITE_P(SecondOrderAndAbove, ExactFreeFall,
                         testing::Values("midpoint", "rk4", "verlet"),
                         integrator_id_name<std::string>);

TEST(EulerFreeFall, ErrorIsExactlyHalfGTimesTDt) {
  for (const double dt : {0.01, 0.005}) {
    const int steps = static_cast<int>(1.0 / dt + 0.5);
    const double t = steps * dt;
    FreeFall fall("euler", steps, dt);
    const double exact = start_position[1] + start_velocity[1] * t - 0.5 * g * t * t;
    EXPECT_NEAR(fall.system.position(0)[1] - exact, -0.5 * g * t * dt, round_off) << "dt " << dt;
    EXPECT_NEAR(fall.system.position(0)[0], start_position[0] + start_velocity[0] * t, round_off);
    expect_exact_velocity(fall.system, t);
  }
}

TEST(VerletFreeFall, WithDragMatchesTheExactSolutionEvenAcrossDtChanges) {
  // x'' = a - c x' with constant a: v(t) = a/c + (start_velocity - a/c) e^{-ct},
  // x(t) = start_position + a t / c + (start_velocity - a/c) (1 - e^{-ct}) / c. Verlet's drag form
  // is exact here, for mild and for overwhelming drag (c dt up to 1e4, where e^{c dt} overflows).
  const Vec3 a{0.0, -g, 0.0};
  for (const double c : {2.0, 1e4}) {
    MockSystem<double> system(1, {}, gravity);
    system.set_position(0, start_position);
    system.set_velocity(0, start_velocity);
    Integrator verlet("verlet");
    verlet.with("damping", c).start(system);
    double t = 0.0;
    for (const double dt : {0.01, 0.02, 0.005, 1.0})
      for (int n = 0; n < 10; ++n, t += dt) ASSERT_EQ(verlet.step(system, t, dt), CLOTHLAB_OK);
    for (int k = 0; k < 3; ++k) {
      const double drift = start_velocity[k] - a[k] / c, decay = std::exp(-c * t);
      const double scale = 1.0 + std::abs(start_position[k]) + std::abs(a[k] * t / c);
      EXPECT_NEAR(system.position(0)[k],
                  start_position[k] + a[k] * t / c + drift * (1.0 - decay) / c, 1e-13 * scale)
          << "c " << c << " component " << k;
      EXPECT_NEAR(system.velocity(0)[k], a[k] / c + drift * decay, 1e-13) << "c " << c;
    }
  }
}

}  // namespace
}  // namespace clothlab::test
