// implicit_euler, bdf2, projective_dynamics and vbd on small spring networks (spring_host.hpp):
// against the analytic backward-Euler (and BDF2) steps of a linear chain, by measured order,
// against each other (converged projective dynamics and vertex block descent = backward Euler on
// the same springs), and for what they report through clothlab.solver-statistics/1.
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <string>
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
  if (extension == nullptr) {
    ADD_FAILURE() << integrator.descriptor().id << " offers no solver statistics";
    return out;
  }
  EXPECT_EQ(extension->last_step(integrator.instance(), &out), CLOTHLAB_OK);
  return out;
}

// A chain along x: particle 0 pinned at the origin, the others at rest spacing 0.1 m.
std::vector<TestSpring> axial_chain_springs() {
  return {{0, 1, 0.1, 50.0, 0.5}, {1, 2, 0.1, 80.0, 0.2}, {2, 3, 0.1, 30.0, 0.4}};
}

// The chain's linear ODE u'' = -K u - D u' (u: displacements along x, masses 1).
struct ChainMatrices {
  Eigen::Matrix3d stiffness = Eigen::Matrix3d::Zero(), damping = Eigen::Matrix3d::Zero();
  ChainMatrices() {
    for (const TestSpring& s : axial_chain_springs()) {
      const int a = static_cast<int>(s.first) - 1, b = static_cast<int>(s.second) - 1;
      for (auto [matrix, k] : {std::pair{&stiffness, s.ks}, std::pair{&damping, s.kd}}) {
        (*matrix)(b, b) += k;
        if (a >= 0) (*matrix)(a, a) += k, (*matrix)(a, b) -= k, (*matrix)(b, a) -= k;
      }
    }
  }
};

// The implicit step of the chain from (u^, v^) with the step k:
// (I + k D + k^2 K) v1 = v^ - k K u^, u1 = u^ + k v1.
void analytic_implicit_step(Eigen::Vector3d& u, Eigen::Vector3d& v, const Eigen::Vector3d& u_hat,
                            const Eigen::Vector3d& v_hat, double k) {
  const ChainMatrices chain;
  const Eigen::Matrix3d system =
      Eigen::Matrix3d::Identity() + k * chain.damping + k * k * chain.stiffness;
  v = system.partialPivLu().solve(v_hat - k * chain.stiffness * u_hat);
  u = u_hat + k * v;
}

// Backward Euler: the step from (u0, v0) with k = h.
void analytic_backward_euler(Eigen::Vector3d& u, Eigen::Vector3d& v, double h) {
  const Eigen::Vector3d u0 = u, v0 = v;
  analytic_implicit_step(u, v, u0, v0, h);
}

// BDF2 at a constant step, started by backward Euler: from (4/3 x0 - 1/3 x_1) with k = 2h/3.
struct AnalyticBdf2 {
  Eigen::Vector3d u_before, v_before;
  int steps = 0;
  void operator()(Eigen::Vector3d& u, Eigen::Vector3d& v, double h) {
    const Eigen::Vector3d u0 = u, v0 = v;
    if (steps++ == 0) {
      analytic_backward_euler(u, v, h);
    } else {
      analytic_implicit_step(u, v, (4 * u0 - u_before) / 3, (4 * v0 - v_before) / 3, 2 * h / 3);
    }
    u_before = u0, v_before = v0;
  }
};

// 25 steps of `integrator` on the chain stretched and moving along x, against `analytic`'s.
template <class Analytic = decltype(analytic_backward_euler)&>
void expect_analytic_chain_steps(Integrator& integrator,
                                 Analytic&& analytic = analytic_backward_euler) {
  SpringHost<double> network(4, {0}, axial_chain_springs(), {0, 0, 0});
  MockSystem<double>& system = network.system();
  Eigen::Vector3d u{0.02, -0.01, 0.03}, v{0.5, 0.0, -0.4};
  for (uint32_t i = 0; i < 4; ++i) {
    system.set_position(i, {0.1 * i + (i > 0 ? u[i - 1] : 0.0), 0, 0});
    system.set_velocity(i, {i > 0 ? v[i - 1] : 0.0, 0, 0});
  }
  integrator.start(system);
  const double h = 0.02;
  for (int step = 0; step < 25; ++step) {
    ASSERT_EQ(integrator.step(system, step * h, h), CLOTHLAB_OK) << integrator.message();
    analytic(u, v, h);
  }
  for (uint32_t i = 1; i < 4; ++i) {
    EXPECT_NEAR(system.position(i)[0], 0.1 * i + u[i - 1], 1e-11) << "particle " << i;
    EXPECT_NEAR(system.velocity(i)[0], v[i - 1], 1e-10) << "particle " << i;
    EXPECT_EQ(system.position(i)[1], 0.0);
    EXPECT_EQ(system.position(i)[2], 0.0);
  }
  EXPECT_EQ(system.position(0), (Vec3{0, 0, 0}));  // pinned: untouched
}

TEST(ImplicitEuler, MatchesTheAnalyticBackwardEulerStepOfALinearChain) {
  Integrator integrator("implicit_euler");
  integrator.with("tolerance", 1e-13);
  expect_analytic_chain_steps(integrator);
}

TEST(Bdf2, MatchesTheAnalyticBdf2StepsOfALinearChain) {
  Integrator integrator("bdf2");
  integrator.with("tolerance", 1e-13);
  expect_analytic_chain_steps(integrator, AnalyticBdf2{});
}

// Along a line the springs are linear: converged block descent is the same backward Euler.
TEST(Vbd, MatchesTheAnalyticBackwardEulerStepOfALinearChain) {
  Integrator integrator("vbd");
  integrator.with("iterations", 200);
  expect_analytic_chain_steps(integrator);
}

// Three particles hanging in a triangle from particle 0: nonlinear springs and gravity.
struct Pendulum {
  static std::vector<TestSpring> springs() {
    return {{0, 1, 0.3, 40.0, 0.05}, {1, 2, 0.25, 60.0, 0.05}, {0, 2, 0.4, 30.0, 0.05}};
  }
  template <class Real>
  static void place(SpringHost<Real>& network) {
    MockSystem<Real>& system = network.system();
    system.set_position(0, {0, 0, 0});
    system.set_position(1, {0.25, -0.2, 0.05});
    system.set_position(2, {0.1, -0.45, -0.1});
    system.set_velocity(1, {0.3, 0.1, 0.0});
    system.set_velocity(2, {-0.2, 0.0, 0.4});
  }
};

std::vector<Vec3> run_pendulum(const std::string& id, double h, int steps,
                               std::vector<std::pair<std::string, double>> params = {},
                               std::vector<TestSpring> springs = Pendulum::springs()) {
  SpringHost<double> network(3, {0}, std::move(springs), {0, -9.81, 0});
  Pendulum::place(network);
  Integrator integrator(id);
  for (const auto& [name, value] : params) integrator.with(name, value);
  integrator.start(network.system());
  integrator.run(network.system(), steps, h);
  return {network.system().position(1), network.system().position(2), network.system().velocity(1)};
}

double distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double largest = 0;
  for (size_t p = 0; p < a.size(); ++p)
    for (int k = 0; k < 3; ++k) largest = std::max(largest, std::abs(a[p][k] - b[p][k]));
  return largest;
}

TEST(ImplicitEuler, IsFirstOrderOnANonlinearNetwork) {
  const double duration = 0.4;
  const std::vector<Vec3> reference = run_pendulum("rk4", duration / 4000, 4000);
  std::vector<double> errors;
  for (int steps : {40, 80, 160})
    errors.push_back(
        distance(run_pendulum("implicit_euler", duration / steps, steps, {{"tolerance", 1e-12}}),
                 reference));
  for (size_t k = 1; k < errors.size(); ++k) {
    const double order = std::log2(errors[k - 1] / errors[k]);
    EXPECT_NEAR(order, 1.0, 0.15) << "errors " << errors[k - 1] << " -> " << errors[k];
  }
}

// One Newton step linearised at the extrapolated state keeps the second order.
TEST(Bdf2, IsSecondOrderOnANonlinearNetwork) {
  const double duration = 0.4;
  const std::vector<Vec3> reference = run_pendulum("rk4", duration / 4000, 4000);
  std::vector<double> errors;
  for (int steps : {40, 80, 160})
    errors.push_back(
        distance(run_pendulum("bdf2", duration / steps, steps, {{"tolerance", 1e-12}}), reference));
  for (size_t k = 1; k < errors.size(); ++k) {
    const double order = std::log2(errors[k - 1] / errors[k]);
    EXPECT_NEAR(order, 2.0, 0.2) << "errors " << errors[k - 1] << " -> " << errors[k];
  }
}

// The kinetic plus spring energy of the undamped chain after `steps` steps of h from a stretch.
double undamped_chain_energy(const std::string& id, double h, int steps) {
  std::vector<TestSpring> springs = axial_chain_springs();
  for (TestSpring& spring : springs) spring.kd = 0.0;
  SpringHost<double> network(4, {0}, springs, {0, 0, 0});
  MockSystem<double>& system = network.system();
  for (uint32_t i = 0; i < 4; ++i) system.set_position(i, {0.1 * i + (i == 3 ? 0.02 : 0.0), 0, 0});
  Integrator integrator(id);
  integrator.with("tolerance", 1e-13);
  integrator.start(system);
  integrator.run(system, steps, h);
  double energy = 0;
  for (uint32_t i = 1; i < 4; ++i) energy += 0.5 * system.velocity(i)[0] * system.velocity(i)[0];
  for (const TestSpring& spring : springs) {
    const double stretch =
        system.position(spring.second)[0] - system.position(spring.first)[0] - spring.rest_length;
    energy += 0.5 * spring.ks * stretch * stretch;
  }
  return energy;
}

// Backward Euler damps a mode of frequency omega by O((omega h)^2) a step, BDF2 by O((omega h)^4):
// at h = 0.05 s (omega h from 0.2 to 0.7 on the chain) BDF2 keeps most of the energy over 50
// steps, backward Euler little of it.
TEST(Bdf2, DampsLessThanBackwardEulerAtTheSameStep) {
  const double start = 0.5 * 30.0 * 0.02 * 0.02;  // only the last spring is stretched
  const double bdf2 = undamped_chain_energy("bdf2", 0.05, 50);
  const double backward_euler = undamped_chain_energy("implicit_euler", 0.05, 50);
  EXPECT_LT(bdf2, start);  // L-stable: it still damps
  EXPECT_GT(bdf2, 0.5 * start);
  EXPECT_LT(backward_euler, 0.5 * bdf2);
}

// The id, the order and the traits every method on the implicit step solver declares.
void expect_implicit_solver_descriptor(const Integrator& integrator, const char* id,
                                       uint32_t order) {
  EXPECT_STREQ(integrator.descriptor().id, id);
  EXPECT_EQ(integrator.descriptor().order, order);
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      integrator.descriptor().get_extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  ASSERT_NE(traits, nullptr);
  EXPECT_EQ(traits->flags, CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE |
                               CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS);
  EXPECT_STREQ(traits->iterations_param, "max_iterations");
}

TEST(Bdf2, DeclaresItsTraits) { expect_implicit_solver_descriptor(Integrator("bdf2"), "bdf2", 2); }

// |v1 - v0 - h a(x1, v1)| after one step: how far the step is from backward Euler proper.
double backward_euler_residual(int newton_steps, double h) {
  SpringHost<double> network(3, {0}, Pendulum::springs(), {0, -9.81, 0});
  Pendulum::place(network);
  MockSystem<double>& system = network.system();
  const Vec3 v1_start = system.velocity(1), v2_start = system.velocity(2);
  Integrator integrator("implicit_euler");
  integrator.with("tolerance", 1e-14).with("newton_steps", newton_steps);
  integrator.start(system);
  EXPECT_EQ(integrator.step(system, 0.0, h), CLOTHLAB_OK) << integrator.message();
  std::vector<double> a(3 * system.stride());
  EXPECT_EQ(
      system.raw().eval_acceleration(system.raw().context, h, system.x(), system.v(), a.data()),
      CLOTHLAB_OK);
  double residual = 0;
  for (auto [i, start] : {std::pair{1u, v1_start}, std::pair{2u, v2_start}})
    for (int k = 0; k < 3; ++k)
      residual = std::max(
          residual, std::abs(system.velocity(i)[k] - start[k] - h * a[k * system.stride() + i]));
  return residual;
}

TEST(ImplicitEuler, NewtonStepsConvergeToBackwardEuler) {
  const double h = 0.05;
  const double one = backward_euler_residual(1, h), two = backward_euler_residual(2, h),
               six = backward_euler_residual(6, h);
  EXPECT_GT(one, 1e-4);  // the linearised step is not backward Euler on nonlinear springs
  EXPECT_LT(two, one / 10);
  EXPECT_LT(six, 1e-10);
}

TEST(ImplicitEuler, DeclaresItsTraits) {
  const Integrator integrator("implicit_euler");
  expect_implicit_solver_descriptor(integrator, "implicit_euler", 1);
  EXPECT_EQ(integrator.descriptor().get_extension("clothlab.solver-statistics/2"), nullptr);
}

TEST(ImplicitEuler, ReportsCgIterationsAndAStepThatMissesItsTolerance) {
  for (bool starved : {false, true}) {
    SpringHost<double> network(3, {0}, Pendulum::springs(), {0, -9.81, 0});
    Pendulum::place(network);
    Integrator integrator("implicit_euler");
    if (starved) integrator.with("max_iterations", 1).with("tolerance", 1e-14);
    integrator.start(network.system());
    const int products_before = network.jacobian_products;
    ASSERT_EQ(integrator.step(network.system(), 0.0, 0.05), CLOTHLAB_OK) << integrator.message();
    const clothlab_solver_step_statistics stats = last_step(integrator);
    // One product for the right-hand side, one per CG iteration (the Baraff-Witkin matrix in
    // one product); the first step has no dv to warm-start from.
    EXPECT_EQ(static_cast<uint64_t>(network.jacobian_products - products_before),
              1 + stats.iterations);
    EXPECT_EQ(stats.factorizations, 0u);
    if (starved) {
      EXPECT_EQ(stats.converged, 0u);
      EXPECT_EQ(stats.iterations, 1u);
      EXPECT_GT(stats.residual, 1e-14);
    } else {
      EXPECT_EQ(stats.converged, 1u);
      EXPECT_GE(stats.iterations, 2u);
      EXPECT_LE(stats.residual, 1e-5);
    }
  }
}

// A chain folded to half its rest lengths: compressed springs' transverse stiffness makes
// the exact Newton matrix indefinite at a large h^2 ks / m, and CG breaks down; with it
// dropped (definite, the default) the solve converges.
TEST(ImplicitEuler, TheDefiniteMatrixKeepsCgConvergingOnACompressedCloth) {
  for (bool definite : {false, true}) {
    std::vector<TestSpring> springs;
    for (uint32_t i = 0; i + 1 < 6; ++i) springs.push_back({i, i + 1, 0.2, 400.0, 0.01});
    SpringHost<double> host(6, {0}, springs, {0, -9.81, 0});
    for (uint32_t i = 0; i < 6; ++i)
      host.system().set_position(i, {0.1 * i, 0.01 * (i % 2), 0.02 * (i % 3)});
    Integrator integrator("implicit_euler");
    integrator.with("definite", definite ? 1.0 : 0.0).with("max_iterations", 200);
    integrator.start(host.system());
    ASSERT_EQ(integrator.step(host.system(), 0.0, 0.05), CLOTHLAB_OK) << integrator.message();
    EXPECT_EQ(last_step(integrator).converged, definite ? 1u : 0u) << "definite " << definite;
  }
}

// A stiff square net hanging from its top row, swinging out of its plane: each step's dv is
// close to the last one's, so starting CG there takes fewer iterations to the same relative
// tolerance, and the motion is the same within what that tolerance allows.
TEST(ImplicitEuler, WarmStartSavesIterationsAndKeepsTheSolution) {
  constexpr uint32_t kSide = 12;
  std::vector<TestSpring> springs;
  std::vector<uint32_t> pinned;
  for (uint32_t r = 0; r < kSide; ++r)
    for (uint32_t c = 0; c < kSide; ++c) {
      const uint32_t i = r * kSide + c;
      if (r == 0) pinned.push_back(i);
      if (c + 1 < kSide) springs.push_back({i, i + 1, 0.05, 1e6, 10.0});
      if (r + 1 < kSide) springs.push_back({i, i + kSide, 0.05, 1e6, 10.0});
    }
  uint64_t iterations[2] = {0, 0};
  std::vector<Vec3> final_positions[2];
  for (bool warm : {false, true}) {
    SpringHost<double> host(kSide * kSide, pinned, springs, {0, -9.81, 0});
    for (uint32_t i = 0; i < kSide * kSide; ++i) {
      const double r = i / kSide, c = i % kSide;
      host.system().set_position(i, {0.05 * c, -0.05 * r, 0});
      host.system().set_velocity(i, {0, 0, 0.05 * r});
    }
    Integrator integrator("implicit_euler");
    integrator.with("warm_start", warm ? 1.0 : 0.0).with("tolerance", 1e-4);
    integrator.start(host.system());
    for (int n = 0; n < 30; ++n) {
      ASSERT_EQ(integrator.step(host.system(), n * 0.01, 0.01), CLOTHLAB_OK)
          << integrator.message();
      const clothlab_solver_step_statistics stats = last_step(integrator);
      ASSERT_EQ(stats.converged, 1u) << "step " << n;
      if (n >= 10) iterations[warm] += stats.iterations;  // past the first transient
    }
    for (uint32_t i = 0; i < kSide * kSide; ++i)
      final_positions[warm].push_back(host.system().position(i));
  }
  // A modest saving on this small net; on cloth driven by gravity and wind it is larger
  // (lab/performance.md).
  EXPECT_LT(iterations[1], iterations[0]) << "warm " << iterations[1] << " cold " << iterations[0];
  EXPECT_LT(distance(final_positions[0], final_positions[1]), 1e-5);
}

TEST(ImplicitEuler, RefusesAHostWithoutTheJacobian) {
  MockSystem<double> system(2, {0}, [](double, uint32_t, const double*, const double*, uint32_t) {
    return Vec3{0, 0, 0};
  });
  Integrator integrator("implicit_euler");
  ASSERT_EQ(integrator.create(), CLOTHLAB_OK);
  EXPECT_EQ(integrator.prepare(system), CLOTHLAB_ERROR_UNSUPPORTED);
  EXPECT_NE(integrator.message().find(CLOTHLAB_EXT_JACOBIAN), std::string::npos)
      << integrator.message();
}

// The pendulum's springs with damping kd: none, or strong enough that damping only along the
// springs (eval_acceleration, implicit Euler) and in every direction differ clearly.
std::vector<TestSpring> pendulum_damped_by(double kd) {
  std::vector<TestSpring> springs = Pendulum::springs();
  for (TestSpring& s : springs) s.kd = kd;
  return springs;
}

TEST(ProjectiveDynamics, ConvergesToTheImplicitEulerStepAsIterationsGrow) {
  const double h = 0.01;
  const int steps = 5;
  for (const double kd : {0.0, 2.0}) {
    const std::vector<Vec3> backward_euler =
        run_pendulum("implicit_euler", h, steps, {{"tolerance", 1e-14}, {"newton_steps", 8}},
                     pendulum_damped_by(kd));
    double previous = INFINITY;
    for (int iterations : {1, 2, 4, 8, 64}) {
      const double difference =
          distance(run_pendulum("projective_dynamics", h, steps, {{"iterations", iterations}},
                                pendulum_damped_by(kd)),
                   backward_euler);
      // Each iteration shrinks the gap until it reaches rounding (1e-14 here).
      if (iterations == 1) {
        EXPECT_GT(difference, 1e-6) << "kd " << kd;  // one iteration is far from converged
      }
      if (previous > 1e-12) {
        EXPECT_LT(difference, previous / 2) << iterations << " iterations, kd " << kd;
      }
      previous = difference;
    }
    EXPECT_LT(previous, 1e-12) << "kd " << kd;
  }
}

// Block Gauss-Seidel on the incremental potential: the gap to backward Euler shrinks with every
// doubling of the sweeps, with the springs' damping (a dissipation potential) as without it.
TEST(Vbd, ConvergesToTheImplicitEulerStepAsIterationsGrow) {
  const double h = 0.01;
  const int steps = 5;
  for (const double kd : {0.0, 2.0}) {
    const std::vector<Vec3> backward_euler =
        run_pendulum("implicit_euler", h, steps, {{"tolerance", 1e-14}, {"newton_steps", 8}},
                     pendulum_damped_by(kd));
    for (const double adaptive : {0.0, 1.0}) {
      double previous = INFINITY;
      for (int iterations : {1, 2, 4, 8, 16, 32, 64}) {
        const double difference =
            distance(run_pendulum("vbd", h, steps,
                                  {{"iterations", iterations}, {"adaptive_guess", adaptive}},
                                  pendulum_damped_by(kd)),
                     backward_euler);
        if (iterations == 1) {
          EXPECT_GT(difference, 1e-6) << "kd " << kd;  // one sweep is far from converged
        }
        if (previous > 1e-12) {
          EXPECT_LT(difference, previous / 2)
              << iterations << " iterations, kd " << kd << ", adaptive " << adaptive;
        }
        previous = difference;
      }
      EXPECT_LT(previous, 1e-12) << "kd " << kd << ", adaptive " << adaptive;
    }
  }
}

TEST(ProjectiveDynamics, FactorsOnceAndAgainOnlyWhenTheStepSizeChanges) {
  SpringHost<double> network(3, {0}, Pendulum::springs(), {0, -9.81, 0});
  Pendulum::place(network);
  Integrator integrator("projective_dynamics");
  integrator.start(network.system());
  const struct {
    double h;
    uint64_t factorizations;
  } schedule[] = {{0.01, 1}, {0.01, 0}, {0.01, 0}, {0.02, 1}, {0.02, 0}, {0.01, 1}};
  double t = 0;
  for (const auto& [h, factorizations] : schedule) {
    ASSERT_EQ(integrator.step(network.system(), t, h), CLOTHLAB_OK) << integrator.message();
    EXPECT_EQ(last_step(integrator).factorizations, factorizations) << "t = " << t;
    EXPECT_EQ(last_step(integrator).iterations, 10u);
    t += h;
  }
  // A new binding (stiffness or pins may differ) starts over.
  ASSERT_EQ(integrator.prepare(network.system()), CLOTHLAB_OK) << integrator.message();
  ASSERT_EQ(integrator.step(network.system(), t, 0.01), CLOTHLAB_OK);
  EXPECT_EQ(last_step(integrator).factorizations, 1u);
}

TEST(ProjectiveDynamics, DeclaresItsTraits) {
  const Integrator integrator("projective_dynamics");
  const auto* traits = static_cast<const clothlab_integrator_traits*>(
      integrator.descriptor().get_extension(CLOTHLAB_EXT_INTEGRATOR_TRAITS));
  ASSERT_NE(traits, nullptr);
  EXPECT_EQ(traits->flags, CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE | CLOTHLAB_TRAIT_ITERATIVE |
                               CLOTHLAB_TRAIT_RESOLVES_CONTACTS | CLOTHLAB_TRAIT_MOVES_ATTACHMENTS);
  EXPECT_STREQ(traits->iterations_param, "iterations");
}

// Float32 systems: the same step as in double, to float precision.
TEST(ImplicitIntegrators, Float32StepsFollowFloat64) {
  for (const std::string id : {"implicit_euler", "bdf2", "projective_dynamics", "vbd"}) {
    SpringHost<float> single(3, {0}, Pendulum::springs(), {0, -9.81, 0});
    SpringHost<double> reference(3, {0}, Pendulum::springs(), {0, -9.81, 0});
    Pendulum::place(single);
    Pendulum::place(reference);
    Integrator a(id), b(id);
    a.start(single.system());
    b.start(reference.system());
    a.run(single.system(), 20, 0.01);
    b.run(reference.system(), 20, 0.01);
    for (uint32_t i = 1; i < 3; ++i)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(single.system().position(i)[k], reference.system().position(i)[k], 1e-4)
            << id << " particle " << i;
  }
}

}  // namespace
}  // namespace clothlab::test
