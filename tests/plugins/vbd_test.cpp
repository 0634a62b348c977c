// The vbd plugin on spring networks the mock host publishes (spring_host.hpp): free fall to
// round-off, the adaptive initial guess, compressed springs, pins left alone bit for bit,
// what it reports through clothlab.solver-statistics/1, and a host
// without the topology. Convergence to backward Euler: implicit_integrators_test.cpp; the same
// bits on any thread count: thread_identity_test.cpp.
#include <clothlab/ext/solver_statistics.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

clothlab_solver_step_statistics last_step(const Integrator& integrator) {
  const auto* extension = static_cast<const clothlab_solver_statistics_extension*>(
      integrator.descriptor().get_extension(CLOTHLAB_EXT_SOLVER_STATISTICS));
  clothlab_solver_step_statistics out{};
  out.struct_size = sizeof out;
  EXPECT_NE(extension, nullptr);
  if (extension != nullptr) {
    EXPECT_EQ(extension->last_step(integrator.instance(), &out), CLOTHLAB_OK);
  }
  return out;
}

// A free particle under gravity: backward Euler with a constant force is semi-implicit Euler,
//   v_n = v0 - g t,  y_n = y0 + v0 t - g t^2 / 2 - g t h / 2,
// and one block step solves the (quadratic) potential exactly, from either initial guess.
TEST(Vbd, FreeFallIsBackwardEulerToRoundOff) {
  const Vec3 x0{1.0, 2.0, 3.0}, v0{0.5, 1.0, -0.25};
  for (const double adaptive : {0.0, 1.0}) {
    SpringHost<double> host(1, {}, {}, {0, -g, 0});
    MockSystem<double>& system = host.system();
    system.set_position(0, x0);
    system.set_velocity(0, v0);
    Integrator vbd("vbd");
    vbd.with("iterations", 1).with("adaptive_guess", adaptive);
    vbd.start(system);
    const int steps = 100;
    const double h = 0.01, t = steps * h;
    vbd.run(system, steps, h);
    const Vec3 x = system.position(0), v = system.velocity(0);
    EXPECT_NEAR(x[0], x0[0] + v0[0] * t, 1e-12);
    EXPECT_NEAR(x[1], x0[1] + v0[1] * t - 0.5 * g * t * t - 0.5 * g * t * h, 1e-12);
    EXPECT_NEAR(x[2], x0[2] + v0[2] * t, 1e-12);
    EXPECT_NEAR(v[0], v0[0], 1e-12);
    EXPECT_NEAR(v[1], v0[1] - g * t, 1e-12);
    EXPECT_NEAR(v[2], v0[2], 1e-12);
  }
}

// A vertical chain of unit masses hanging from particle 0 at its static equilibrium, at rest.
template <class Real>
struct RestingChain {
  static constexpr uint32_t count = 5;
  static constexpr double spacing = 0.1, ks = 200.0;
  static std::vector<TestSpring> springs() {
    std::vector<TestSpring> out;
    for (uint32_t i = 0; i + 1 < count; ++i) out.push_back({i, i + 1, spacing, ks, 0.5});
    return out;
  }
  RestingChain() : host(count, {0}, springs(), {0, -g, 0}) {
    double y = 0;
    for (uint32_t i = 0; i < count; ++i) {
      host.system().set_position(i, {0, y, 0});
      y -= spacing + (count - 1 - i) * g / ks;  // spring i carries the masses below it
    }
  }
  double largest_speed() {
    double largest = 0;
    for (uint32_t i = 0; i < count; ++i)
      for (double component : host.system().velocity(i))
        largest = std::max(largest, std::abs(component));
    return largest;
  }
  SpringHost<Real> host;
};

// The adaptive guess reads the last step's acceleration: a resting cloth has little, so the
// guess starts near where it rests, while inertia starts it a free fall (h^2 g) away. With one
// sweep a step, the chain at rest then stays near rest from the adaptive guess (about 1e-3 m/s
// after 20 steps), and jitters a hundred times faster from inertia.
TEST(Vbd, AdaptiveGuessKeepsARestingClothNearRest) {
  const auto speed_after = [](bool adaptive) {
    RestingChain<double> chain;
    Integrator vbd("vbd");
    vbd.with("iterations", 1).with("adaptive_guess", adaptive ? 1.0 : 0.0);
    vbd.start(chain.host.system());
    vbd.run(chain.host.system(), 20, 1.0 / 60);
    return chain.largest_speed();
  };
  const double adaptive = speed_after(true), inertia = speed_after(false);
  EXPECT_LT(adaptive, 5e-3);
  EXPECT_GT(inertia, 20 * adaptive);
}

// A particle between two pins, its springs compressed to a fifth of their rest length and
// nudged 1 cm off the line: the springs push it out (it buckles). Unclamped, the transverse
// stiffness ks (1 - l0/l) is -4 ks per spring, the block's Hessian indefinite (m/h^2 = 100 against
// -8000), and its Newton step jumps back to the line instead (the saddle).
TEST(Vbd, CompressedSpringsBuckleOutward) {
  SpringHost<double> host(3, {0, 2}, {{0, 1, 1.0, 1000.0, 0.0}, {1, 2, 1.0, 1000.0, 0.0}},
                          {0, 0, 0});
  MockSystem<double>& system = host.system();
  system.set_position(0, {-0.2, 0, 0});
  system.set_position(1, {0, 0.01, 0});
  system.set_position(2, {0.2, 0, 0});
  Integrator vbd("vbd");
  vbd.with("iterations", 1);
  vbd.start(system);
  ASSERT_EQ(vbd.step(system, 0.0, 0.1), CLOTHLAB_OK) << vbd.message();
  EXPECT_GT(system.position(1)[1], 0.1);
  EXPECT_GT(system.velocity(1)[1], 0.0);
}

template <class Real>
void expect_pins_untouched() {
  RestingChain<Real> chain;
  MockSystem<Real>& system = chain.host.system();
  system.set_velocity(0, {0.5, -0.25, 1.0});  // a pin's velocity is the host's, never used
  system.set_velocity(3, {0.3, 0.1, -0.2});
  const Vec3 pin = system.position(0), pin_velocity = system.velocity(0);
  Integrator vbd("vbd");
  vbd.start(system);
  vbd.run(system, 50, 1.0 / 60);
  // Vec3 holds the Real values exactly, so equal bits there are equal bits in the state.
  const Vec3 pin_now = system.position(0), pin_velocity_now = system.velocity(0);
  EXPECT_EQ(std::memcmp(&pin_now, &pin, sizeof pin), 0);
  EXPECT_EQ(std::memcmp(&pin_velocity_now, &pin_velocity, sizeof pin), 0);
  EXPECT_GT(std::abs(system.position(3)[0]), 1e-3) << "the free particles must move";
}

TEST(Vbd, PinnedParticlesStayBitForBitFloat64) { expect_pins_untouched<double>(); }
TEST(Vbd, PinnedParticlesStayBitForBitFloat32) { expect_pins_untouched<float>(); }

// The sweeps it ran and the last sweep's largest correction relative to the step's motion:
// small once converged, large after one sweep on a stiff, moving cloth.
TEST(Vbd, ReportsItsSweepsAndHowFarTheLastOneMoved) {
  const auto report = [](int iterations) {
    RestingChain<double> chain;
    chain.host.system().set_velocity(4, {1.0, 0.5, 0.0});
    Integrator vbd("vbd");
    vbd.with("iterations", iterations);
    vbd.start(chain.host.system());
    vbd.run(chain.host.system(), 3, 1.0 / 60);
    return last_step(vbd);
  };
  const clothlab_solver_step_statistics one = report(1), many = report(200);
  EXPECT_EQ(one.iterations, 1u);
  EXPECT_EQ(many.iterations, 200u);
  EXPECT_EQ(many.converged, 1u);
  EXPECT_GT(one.residual, 1e-3);
  EXPECT_LT(many.residual, 1e-12);
}

TEST(Vbd, WithoutTheTopologyExtensionPrepareFailsWithOneLine) {
  MockSystem<double> bare(2, {0}, [](double, uint32_t, const double*, const double*, uint32_t) {
    return Vec3{0, 0, 0};
  });
  Integrator vbd("vbd");
  ASSERT_EQ(vbd.create(), CLOTHLAB_OK) << vbd.message();
  EXPECT_EQ(vbd.prepare(bare), CLOTHLAB_ERROR_UNSUPPORTED);
  EXPECT_NE(vbd.message().find("clothlab.topology/1"), std::string::npos) << vbd.message();
  EXPECT_EQ(vbd.message().find('\n'), std::string::npos) << vbd.message();
}

TEST(Vbd, RejectsZeroIterations) {
  Integrator vbd("vbd");
  vbd.with("iterations", 0);
  EXPECT_EQ(vbd.create(), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(vbd.message().find("iterations"), std::string::npos) << vbd.message();
}

}  // namespace
}  // namespace clothlab::test
