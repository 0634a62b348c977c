// The xpbd plugin against analytic solutions on spring networks the mock host publishes
// through the topology and external-forces extensions (spring_host.hpp): the static sag of a
// hanging chain (Hooke's law, in the soft and the stiff regime), the period of a single spring and
// of a stiff pendulum (the constrained limit), independence of the iteration count (lambda is reset
// once per substep, not per iteration: newton#2933), pins left alone. Tethers themselves:
// xpbd_tethers_test.cpp; bitwise identity across thread counts: thread_identity_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

std::vector<TestSpring> chain_springs(uint32_t count, double spacing, double ks, double kd) {
  std::vector<TestSpring> springs;
  for (uint32_t i = 0; i + 1 < count; ++i) springs.push_back({i, i + 1, spacing, ks, kd});
  return springs;
}

// A vertical chain of `count` unit masses spaced `spacing` below particle 0 (pinned), joined
// by springs (ks, kd), under gravity; colours alternate so no two springs of a colour share
// a particle.
template <class Real>
struct HangingChain {
  HangingChain(uint32_t count, double spacing, double ks, double kd)
      : network(count, {0}, chain_springs(count, spacing, ks, kd), {0, -g, 0}) {
    std::vector<std::vector<uint32_t>> colors(2);
    for (uint32_t k = 0; k + 1 < count; ++k) colors[k % 2].push_back(k);
    network.set_spring_colors(colors);
    for (uint32_t i = 0; i < count; ++i) system().set_position(i, {0, -spacing * i, 0});
  }
  MockSystem<Real>& system() { return network.system(); }

  // Equilibrium height of particle i: spring p carries the (count - 1 - p) masses below it.
  static double equilibrium_y(uint32_t count, uint32_t i, double spacing, double ks) {
    double y = 0;
    for (uint32_t p = 0; p < i; ++p) y -= spacing + (count - 1 - p) * g / ks;
    return y;
  }

  SpringHost<Real> network;
};

constexpr uint32_t chain_count = 6;
constexpr double chain_spacing = 0.1;
constexpr double chain_damping_ratio = 0.01;  // kd / ks, s: settles the chain within 40 s
constexpr double chain_dt = 0.01;
constexpr int chain_substeps = 10;

// With few iterations a substep's single sweep does not bring the damping term of eq. 26
// (kd h n.(dx_i - dx_j)) to zero: each substep's gravity drift h^2 g meets a damping force
// ~ kd h g per carried mass, so the chain settles stretched by up to (kd / ks) h g per mass
// carried, summed over the springs. It vanishes with h (first order) and with converged
// iterations; it does not depend on ks.
double one_sweep_bias_bound() {
  const double h = chain_dt / chain_substeps;
  return 1.5 * chain_damping_ratio * h * g * (chain_count - 1) * chain_count / 2;
}

// Settles a damped chain and returns the largest deviation from Hooke's equilibrium.
template <class Real>
double chain_sag_error(double ks, int iterations) {
  HangingChain<Real> chain(chain_count, chain_spacing, ks, chain_damping_ratio * ks);
  Integrator xpbd("xpbd");
  xpbd.with("iterations", iterations).with("inner_substeps", chain_substeps).with("threads", 1);
  xpbd.start(chain.system());
  xpbd.run(chain.system(), 4000, chain_dt);  // 40 s
  double error = 0;
  for (uint32_t i = 0; i < chain_count; ++i) {
    const Vec3 p = chain.system().position(i);
    const double exact = HangingChain<Real>::equilibrium_y(chain_count, i, chain_spacing, ks);
    error = std::max({error, std::abs(p[1] - exact), std::abs(p[0]), std::abs(p[2])});
  }
  EXPECT_EQ(chain.system().position(0), (Vec3{0, 0, 0})) << "the pin moved";
  return error;
}

TEST(Xpbd, HangingChainSettlesAtHookesSagForAnyIterationCount) {
  // ks = 1000 N/m: the chain sags 0.147 m, its top spring stretches by 49 %. A lambda
  // reset per iteration would stiffen the chain with every extra iteration.
  EXPECT_LT(chain_sag_error<double>(1000.0, 1), one_sweep_bias_bound());
  for (int iterations : {4, 16})
    EXPECT_LT(chain_sag_error<double>(1000.0, iterations), 1e-8) << "iterations " << iterations;
}

TEST(Xpbd, StiffHangingChainStaysWithinTheOneSweepBias) {
  // ks = 1e6 N/m, h = 1 ms: alpha / h^2 = 1 is below the inverse masses, the stiff regime
  // where the constraints, not the compliance, set each projection (static sag 0.15 mm).
  double previous = 1.0;
  for (int iterations : {1, 4, 16}) {
    const double error = chain_sag_error<double>(1.0e6, iterations);
    EXPECT_LT(error, one_sweep_bias_bound()) << "iterations " << iterations;
    EXPECT_LT(error, previous) << "more iterations, further from Hooke: " << iterations;
    previous = error;
  }
}

TEST(Xpbd, HangingChainInFloat32) {
  EXPECT_LT(chain_sag_error<float>(1000.0, 1), one_sweep_bias_bound());
  // Each substep moves float32 positions of ~0.6 m by ~h^2 g = 1e-5 m, resolved to ~6e-8 m:
  // the rounding of those increments, not the solver, limits the converged sag.
  EXPECT_LT(chain_sag_error<float>(1000.0, 16), 1e-4);
}

// Upward zero crossings of y(t) - center, interpolated linearly; the mean spacing.
double measured_period(const std::vector<double>& y, double center, double dt) {
  std::vector<double> crossings;
  for (size_t n = 1; n < y.size(); ++n)
    if (y[n - 1] < center && y[n] >= center)
      crossings.push_back((n - 1 + (center - y[n - 1]) / (y[n] - y[n - 1])) * dt);
  if (crossings.size() < 2) return 0;
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

// An undamped unit mass on a spring from a pin, no gravity, started 0.1 m stretched.
double spring_period(int iterations) {
  constexpr double ks = 10.0, dt = 1e-3;
  SpringHost<double> network(2, {0}, {{0, 1, 1.0, ks, 0.0}}, {0, 0, 0});
  MockSystem<double>& system = network.system();
  system.set_position(1, {0, -1.1, 0});
  Integrator xpbd("xpbd");
  xpbd.with("iterations", iterations).with("inner_substeps", 10);
  xpbd.start(system);
  std::vector<double> y;
  for (int n = 0; n < 7000; ++n) {  // 3.5 periods
    EXPECT_EQ(xpbd.step(system, n * dt, dt), CLOTHLAB_OK) << xpbd.message();
    y.push_back(system.position(1)[1]);
  }
  return measured_period(y, -1.0, dt);
}

TEST(Xpbd, SpringPeriodIsAnalyticAndIndependentOfTheIterationCount) {
  const double exact = 2 * std::numbers::pi / std::sqrt(10.0);
  const double one = spring_period(1);
  EXPECT_NEAR(one, exact, 1e-3 * exact);
  for (int iterations : {2, 8, 32})
    EXPECT_NEAR(spring_period(iterations), one, 1e-9 * exact) << "iterations " << iterations;
}

TEST(Xpbd, StiffSpringPendulumHasTheRigidPendulumPeriod) {
  // ks = 1e7 N/m on a 1 m, 1 kg pendulum: the stiff (constrained) limit, period
  // 2 pi sqrt(L / g) (1 + theta0^2 / 16) for a 0.05 rad swing.
  constexpr double theta0 = 0.05, dt = 0.01;
  SpringHost<double> network(2, {0}, {{0, 1, 1.0, 1.0e7, 0.0}}, {0, -g, 0});
  MockSystem<double>& system = network.system();
  system.set_position(1, {std::sin(theta0), -std::cos(theta0), 0});
  Integrator xpbd("xpbd");
  xpbd.with("inner_substeps", 20);
  xpbd.start(system);
  std::vector<double> x;
  double worst_length_error = 0;
  for (int n = 0; n < 700; ++n) {  // 3.5 periods
    ASSERT_EQ(xpbd.step(system, n * dt, dt), CLOTHLAB_OK) << xpbd.message();
    const Vec3 p = system.position(1);
    x.push_back(p[0]);
    worst_length_error = std::max(worst_length_error, std::abs(std::hypot(p[0], p[1]) - 1.0));
  }
  const double exact = 2 * std::numbers::pi * std::sqrt(1.0 / g) * (1 + theta0 * theta0 / 16);
  EXPECT_NEAR(measured_period(x, 0.0, dt), exact, 2e-3 * exact);
  EXPECT_LT(worst_length_error, 1e-5);  // the static stretch m g / ks is 1e-6 m
}

TEST(Xpbd, ZeroStepLeavesTheStateAlone) {
  HangingChain<double> chain(4, 0.1, 100.0, 0.1);
  Integrator xpbd("xpbd");
  xpbd.start(chain.system());
  xpbd.run(chain.system(), 3, 0.01);
  const Vec3 before = chain.system().position(3), speed = chain.system().velocity(3);
  ASSERT_EQ(xpbd.step(chain.system(), 0.03, 0.0), CLOTHLAB_OK) << xpbd.message();
  EXPECT_EQ(chain.system().position(3), before);
  EXPECT_EQ(chain.system().velocity(3), speed);
}

// The general sweep's velocity pass reports a speed that is not finite: a chain of 300 (its
// passes run in blocks of particles, so the particle lies in a later block) with one particle
// started at infinite speed.
template <class Real>
clothlab_status chain_step_with_an_infinite_speed() {
  HangingChain<Real> chain(300, 0.01, 100.0, 0.1);
  chain.system().set_velocity(290, {0, 0, std::numeric_limits<double>::infinity()});
  Integrator xpbd("xpbd");
  xpbd.with("threads", 1);
  xpbd.start(chain.system());
  return xpbd.step(chain.system(), 0.0, 1e-3);
}

TEST(Xpbd, ReportsANonFiniteSpeedAsNumerical) {
  EXPECT_EQ(chain_step_with_an_infinite_speed<float>(), CLOTHLAB_ERROR_NUMERICAL);
  EXPECT_EQ(chain_step_with_an_infinite_speed<double>(), CLOTHLAB_ERROR_NUMERICAL);
}

TEST(Xpbd, WithoutTheTopologyExtensionPrepareFailsWithOneLine) {
  MockSystem<double> bare(2, {0}, [](double, uint32_t, const double*, const double*, uint32_t) {
    return Vec3{0, 0, 0};
  });
  Integrator xpbd("xpbd");
  ASSERT_EQ(xpbd.create(), CLOTHLAB_OK) << xpbd.message();
  EXPECT_EQ(xpbd.prepare(bare), CLOTHLAB_ERROR_UNSUPPORTED);
  EXPECT_NE(xpbd.message().find("clothlab.topology/1"), std::string::npos) << xpbd.message();
}

TEST(Xpbd, RejectsZeroSubsteps) {
  Integrator xpbd("xpbd");
  xpbd.with("inner_substeps", 0);
  EXPECT_EQ(xpbd.create(), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(xpbd.message().find("inner_substeps"), std::string::npos) << xpbd.message();
}

}  // namespace
}  // namespace clothlab::test
