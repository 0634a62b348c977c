// Measured order of convergence on a harmonic oscillator with a known solution,
//   x'' = -w^2 x - 2 zeta w x',   x(0) = x0, x'(0) = v0,
//   x(t) = e^{-zeta w t} (x0 cos(wd t) + (v0 + zeta w x0) / wd sin(wd t)),
//   v(t) = e^{-zeta w t} (v0 cos(wd t) - (zeta w v0 + w^2 x0) / wd sin(wd t)),
// with wd = w sqrt(1 - zeta^2). The error at t = T for dt = T/N, N = 50, 100, 200, 400,
// is fitted by least squares in log-log; the slope must lie within 0.2 of the declared
// order. The damped case gives the damping to the force law (euler, midpoint, rk4) or
// to Verlet's own damping rate c = 2 zeta w (Verlet passes no velocities).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "integrator_harness.hpp"

namespace clothlab::test {
namespace {

constexpr double w = 2.0 * std::numbers::pi;
constexpr double x0 = 1.0, v0 = 0.3, duration = 1.3;

struct Oscillator {
  double zeta;

  double error_after(const std::string& id, int steps) const {
    const double z = zeta;
    MockSystem<double> system(1, {},
                              [z](double, uint32_t, const double* x, const double* v, uint32_t) {
                                double a = -w * w * x[0];
                                if (v != nullptr) a -= 2.0 * z * w * v[0];
                                return Vec3{a, 0.0, 0.0};
                              });
    system.set_position(0, {x0, 0.0, 0.0});
    system.set_velocity(0, {v0, 0.0, 0.0});
    Integrator integrator(id);
    if (id == "verlet") integrator.with("damping", 2.0 * zeta * w);
    integrator.start(system);
    integrator.run(system, steps, duration / steps);

    const double wd = w * std::sqrt(1.0 - zeta * zeta), decay = std::exp(-zeta * w * duration);
    const double c = std::cos(wd * duration), s = std::sin(wd * duration);
    const double x = decay * (x0 * c + (v0 + zeta * w * x0) / wd * s);
    const double v = decay * (v0 * c - (zeta * w * v0 + w * w * x0) / wd * s);
    return std::max(std::abs(system.position(0)[0] - x), std::abs(system.velocity(0)[0] - v) / w);
  }

  // Least-squares slope of log(error) against log(dt).
  double measured_order(const std::string& id) const {
    std::vector<double> log_dt, log_error;
    for (int steps : {50, 100, 200, 400}) {
      log_dt.push_back(std::log(duration / steps));
      log_error.push_back(std::log(error_after(id, steps)));
    }
    const double n = static_cast<double>(log_dt.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (size_t i = 0; i < log_dt.size(); ++i) {
      sx += log_dt[i];
      sy += log_error[i];
      sxx += log_dt[i] * log_dt[i];
      sxy += log_dt[i] * log_error[i];
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
  }
};

double declared_order(const std::string& id) { return Integrator(id).descriptor().order; }

class Convergence : public testing::TestWithParam<std::string> {};

TEST_P(Convergence, UndampedOscillatorShowsTheDeclaredOrder) {
  const std::string id = GetParam();
  EXPECT_NEAR(Oscillator{0.0}.measured_order(id), declared_order(id), 0.2);
}

TEST_P(Convergence, DampedOscillatorShowsTheDeclaredOrder) {
  const std::string id = GetParam();
  EXPECT_NEAR(Oscillator{0.1}.measured_order(id), declared_order(id), 0.2);
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, Convergence,
                         testing::Values("euler", "midpoint", "rk4", "verlet"),
                         integrator_id_name<std::string>);

}  // namespace
}  // namespace clothlab::test
