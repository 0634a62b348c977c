// What every integrator promises through the ABI, beyond accuracy: declared metadata,
// cost, pinned particles and dt = 0 left alone bit for bit, errors reported, parameters
// validated.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "integrator_harness.hpp"

namespace clothlab::test {
namespace {

struct Declared {
  uint32_t order, evals_per_step;
  bool velocity_forces;
};

Declared expected_declaration(const std::string& id) {
  if (id == "euler") return {1, 1, true};
  if (id == "midpoint") return {2, 2, true};
  if (id == "rk4") return {4, 4, true};
  return {2, 1, false};  // verlet
}

// A chain 0-1-2-3 with 0 and 2 pinned (active ranges {1} and {3}), springs between
// neighbours, gravity and, when velocities come, damping relative to the neighbours.
template <class Real>
Vec3 chain(double, uint32_t i, const Real* x, const Real* v, uint32_t stride) {
  Vec3 a{0.0, -9.81, 0.0};
  for (uint32_t j : {i - 1, i + 1}) {
    if (j > 3) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      a[k] += 50.0 * (x[k * stride + j] - x[k * stride + i]);
      if (v != nullptr) a[k] += 0.5 * (v[k * stride + j] - v[k * stride + i]);
    }
  }
  return a;
}

template <class Real>
struct Chain {
  Chain() : system(4, {0, 2}, chain<Real>) {
    // Odd values, a negative zero and non-zero pinned velocities: none may change.
    system.set_position(0, {1.0 / 3.0, -0.0, 1e-7});
    system.set_velocity(0, {0.25, -0.5, 1.0 / 7.0});
    system.set_position(1, {0.4, -0.1, 0.05});
    system.set_position(2, {0.9, 0.2, -0.0});
    system.set_velocity(2, {-0.125, 0.0, 3.0});
    system.set_position(3, {1.3, -0.3, 0.1});
    system.set_velocity(3, {0.0, 0.2, -0.0});
  }
  std::vector<Real> snapshot() {
    const size_t size = 3 * size_t{system.stride()};
    std::vector<Real> state(system.x(), system.x() + size);
    state.insert(state.end(), system.v(), system.v() + size);
    return state;
  }
  MockSystem<Real> system;
};

template <class Real>
bool same_bits(const Vec3& a, const Vec3& b) {
  for (int k = 0; k < 3; ++k) {
    const Real ra = static_cast<Real>(a[k]), rb = static_cast<Real>(b[k]);
    if (std::memcmp(&ra, &rb, sizeof(Real)) != 0) return false;
  }
  return true;
}

class IntegratorContract : public testing::TestWithParam<std::string> {};

TEST_P(IntegratorContract, DeclaresItsOrderCostFlagsAndPrecisions) {
  const Integrator integrator(GetParam());
  const clothlab_integrator& d = integrator.descriptor();
  const Declared expected = expected_declaration(GetParam());
  EXPECT_EQ(std::string(d.id), GetParam());
  EXPECT_EQ(d.order, expected.order);
  EXPECT_EQ(d.evals_per_step, expected.evals_per_step);
  EXPECT_EQ((d.flags & CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES) != 0, expected.velocity_forces);
  EXPECT_EQ(d.precisions, (1u << CLOTHLAB_FLOAT32) | (1u << CLOTHLAB_FLOAT64));
}

TEST_P(IntegratorContract, EvaluatesForcesAsOftenAsDeclaredAndAsksForVelocitiesOnlyIfFlagged) {
  Chain<double> chain;
  Integrator integrator(GetParam());
  integrator.start(chain.system);
  integrator.run(chain.system, 10, 1e-3);
  const Declared expected = expected_declaration(GetParam());
  EXPECT_EQ(chain.system.evaluations, 10 * static_cast<int>(expected.evals_per_step));
  EXPECT_EQ(chain.system.evaluations_without_velocity,
            expected.velocity_forces ? 0 : chain.system.evaluations);
}

template <class Real>
void expect_pinned_untouched(const std::string& id) {
  Chain<Real> chain;
  const Vec3 x0 = chain.system.position(0), v0 = chain.system.velocity(0);
  const Vec3 x2 = chain.system.position(2), v2 = chain.system.velocity(2);
  Integrator integrator(id);
  integrator.start(chain.system);
  integrator.run(chain.system, 500, 1e-3);
  EXPECT_TRUE(same_bits<Real>(chain.system.position(0), x0));
  EXPECT_TRUE(same_bits<Real>(chain.system.velocity(0), v0));
  EXPECT_TRUE(same_bits<Real>(chain.system.position(2), x2));
  EXPECT_TRUE(same_bits<Real>(chain.system.velocity(2), v2));
  EXPECT_NE(chain.system.position(1), (Vec3{0.4, -0.1, 0.05})) << "the free particles must move";
}

TEST_P(IntegratorContract, PinnedParticlesStayBitForBitFloat64) {
  expect_pinned_untouched<double>(GetParam());
}

TEST_P(IntegratorContract, PinnedParticlesStayBitForBitFloat32) {
  expect_pinned_untouched<float>(GetParam());
}

template <class Real>
void expect_zero_step_changes_nothing(const std::string& id) {
  Chain<Real> chain;
  Integrator integrator(id);
  integrator.start(chain.system);
  const std::vector<Real> initial = chain.snapshot();
  ASSERT_EQ(integrator.step(chain.system, 0.0, 0.0), CLOTHLAB_OK) << integrator.message();
  EXPECT_EQ(std::memcmp(chain.snapshot().data(), initial.data(), initial.size() * sizeof(Real)), 0);

  integrator.run(chain.system, 5, 1e-3);
  const std::vector<Real> moved = chain.snapshot();
  ASSERT_EQ(integrator.step(chain.system, 5e-3, 0.0), CLOTHLAB_OK) << integrator.message();
  EXPECT_EQ(std::memcmp(chain.snapshot().data(), moved.data(), moved.size() * sizeof(Real)), 0);
}

TEST_P(IntegratorContract, ZeroStepLeavesTheStateUnchangedFloat64) {
  expect_zero_step_changes_nothing<double>(GetParam());
}

TEST_P(IntegratorContract, ZeroStepLeavesTheStateUnchangedFloat32) {
  expect_zero_step_changes_nothing<float>(GetParam());
}

TEST_P(IntegratorContract, StageStatesCarryThePinnedParticles) {
  // Particle 1 sits between pinned particles 0 and 2 and accelerates by the sum of their
  // positions plus, when velocities come, of their velocities: a constant c, since pinned
  // particles never move. Every stage the force law sees must therefore hold the pins'
  // real state, not zeros. One step:
  //   x1 = x + v dt + c dt^2 / 2 (c dt^2 for semi-implicit Euler),  v1 = v + c dt.
  MockSystem<double> system(
      3, {0, 2}, [](double, uint32_t, const double* x, const double* v, uint32_t stride) {
        Vec3 a{};
        for (uint32_t k = 0; k < 3; ++k)
          for (uint32_t pin : {0u, 2u})
            a[k] += x[k * stride + pin] + (v ? v[k * stride + pin] : 0.0);
        return a;
      });
  system.set_position(0, {1.0, 2.0, 3.0});
  system.set_velocity(0, {4.0, 5.0, 6.0});
  system.set_position(2, {0.5, 0.25, 0.125});
  system.set_velocity(2, {-1.0, -2.0, -4.0});
  Integrator integrator(GetParam());
  if (GetParam() == "verlet") integrator.with("damping", 0.0);
  integrator.start(system);
  const double dt = 0.125;
  integrator.run(system, 1, dt);
  const bool velocities = expected_declaration(GetParam()).velocity_forces;
  const double position_weight = GetParam() == "euler" ? dt * dt : 0.5 * dt * dt;
  const Vec3 from_positions{1.5, 2.25, 3.125}, from_velocities{3.0, 3.0, 2.0};
  for (int k = 0; k < 3; ++k) {
    const double c = from_positions[k] + (velocities ? from_velocities[k] : 0.0);
    EXPECT_NEAR(system.position(1)[k], position_weight * c, 1e-14) << "component " << k;
    EXPECT_NEAR(system.velocity(1)[k], dt * c, 1e-14) << "component " << k;
  }
}

TEST_P(IntegratorContract, RejectsNegativeOrNonFiniteDt) {
  Chain<double> chain;
  Integrator integrator(GetParam());
  integrator.start(chain.system);
  EXPECT_EQ(integrator.step(chain.system, 0.0, -1e-3), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(integrator.step(chain.system, 0.0, std::numeric_limits<double>::quiet_NaN()),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
}

TEST_P(IntegratorContract, StepWithoutPrepareIsAnErrorNotACrash) {
  Chain<double> chain;
  Integrator integrator(GetParam());
  ASSERT_EQ(integrator.create(), CLOTHLAB_OK);
  EXPECT_EQ(integrator.step(chain.system, 0.0, 1e-3), CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(integrator.message().find("prepared"), std::string::npos) << integrator.message();
}

TEST_P(IntegratorContract, CanBeReboundToAnotherSystemAndPrecision) {
  Chain<float> single;
  Chain<double> twin;
  Integrator integrator(GetParam());
  integrator.start(single.system);
  integrator.run(single.system, 3, 1e-3);
  EXPECT_EQ(integrator.step(twin.system, 0.0, 1e-3), CLOTHLAB_ERROR_INVALID_ARGUMENT)
      << "stepping a system it was not prepared for";
  ASSERT_EQ(integrator.prepare(twin.system), CLOTHLAB_OK) << integrator.message();
  integrator.run(twin.system, 3, 1e-3);
}

TEST_P(IntegratorContract, ReportsNonFiniteAccelerationAsNumerical) {
  MockSystem<double> system(1, {}, [](double, uint32_t, const double*, const double*, uint32_t) {
    return Vec3{std::numeric_limits<double>::infinity(), 0.0, 0.0};
  });
  Integrator integrator(GetParam());
  integrator.start(system);
  EXPECT_EQ(integrator.step(system, 0.0, 1e-3), CLOTHLAB_ERROR_NUMERICAL);
  EXPECT_FALSE(integrator.message().empty());
}

TEST_P(IntegratorContract, RejectsAWrongNumberOfParameterValues) {
  const Integrator integrator(GetParam());
  const clothlab_integrator& d = integrator.descriptor();
  std::vector<clothlab_param_value> values(d.param_count + 1);
  void* instance = nullptr;
  clothlab_message message{};
  EXPECT_EQ(d.create(values.data(), d.param_count + 1, &instance, &message),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(instance, nullptr);
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, IntegratorContract,
                         testing::Values("euler", "midpoint", "rk4", "verlet"),
                         integrator_id_name<std::string>);

TEST(VerletParameters, OutOfRangeValuesAreRejectedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, double>> bad{{"damping", -0.1},
                                                        {"damping", nan},
                                                        {"damping", 1e5},
                                                        {"damping_per_step", -0.01},
                                                        {"damping_per_step", 0.6}};
  for (const auto& [name, value] : bad) {
    Integrator verlet("verlet");
    EXPECT_EQ(verlet.with(name, value).create(), CLOTHLAB_ERROR_INVALID_ARGUMENT)
        << name << " = " << value;
    EXPECT_NE(verlet.message().find(name), std::string::npos) << verlet.message();
  }
}

// No drag by default: Verlet integrates the ODE the other built-ins and the conformance
// references integrate.
TEST(VerletParameters, DefaultsAreNoDragAndNoPerStepDamping) {
  const Integrator verlet("verlet");
  const clothlab_integrator& d = verlet.descriptor();
  ASSERT_EQ(d.param_count, 2u);
  EXPECT_STREQ(d.params[0].name, "damping");
  EXPECT_EQ(d.params[0].default_value[0], 0.0);
  EXPECT_STREQ(d.params[0].unit, "1/s");
  EXPECT_STREQ(d.params[1].name, "damping_per_step");
  EXPECT_EQ(d.params[1].default_value[0], 0.0);
}

TEST(VerletHistory, RestartsWhenDtChangesSoFreeFallStaysExact) {
  // With the old displacement kept across a dt change the next step would use the
  // wrong velocity; the restart from (x, v) keeps the parabola exact.
  MockSystem<double> system(1, {}, [](double, uint32_t, const double*, const double*, uint32_t) {
    return Vec3{0.0, -9.81, 0.0};
  });
  system.set_velocity(0, {0.0, 2.0, 0.0});
  Integrator verlet("verlet");
  verlet.with("damping", 0.0).start(system);
  double t = 0.0;
  for (const double dt : {0.01, 0.02, 0.005}) {
    for (int n = 0; n < 20; ++n, t += dt) ASSERT_EQ(verlet.step(system, t, dt), CLOTHLAB_OK);
  }
  EXPECT_NEAR(system.position(0)[1], 2.0 * t - 0.5 * 9.81 * t * t, 1e-12);
  EXPECT_NEAR(system.velocity(0)[1], 2.0 - 9.81 * t, 1e-12);
}

}  // namespace
}  // namespace clothlab::test
