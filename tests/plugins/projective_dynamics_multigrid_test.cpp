// projective_dynamics' multigrid global solve (`factorization` = 2,
// multigrid_global_solve.hpp): its solutions against Eigen's SimplicialLDLT on the same matrix,
// its V-cycle count as the grid grows, its steps against the LDLT path's, a solve that misses
// its tolerance reported, and bad settings refused in one line.
#include <clothlab/ext/solver_statistics.h>
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "integrator_harness.hpp"
#include "multigrid_global_solve.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
using builtin::MultigridGlobalSolve;

constexpr double kSpacing = 0.02;

// A cotton-like Provot flag 2 cm apart: structural and shear springs (ks 6000 N/m), flexion
// springs two apart (ks 60 N/m), all damped (kd 0.02).
std::vector<TestSpring> cotton_flag_springs(uint32_t rows, uint32_t cols) {
  return provot_net_springs(rows, cols, kSpacing, 6000.0, 60.0, 0.02);
}

// The global system of a rows x cols flag pinned along its left column, written out here from
// the springs (not the plugin's projective_dynamics_matrix.hpp): unknowns are the free
// particles in row-major order, A = M + h^2 K as its upper triangle, masses 0.4 g.
struct FlagSystem {
  static constexpr double kMass = 4e-4;
  FlagSystem(uint32_t rows, uint32_t cols, double h) : rows(rows), cols(cols) {
    std::vector<int> unknown_of(rows * cols, -1);
    for (uint32_t i = 0; i < rows * cols; ++i) {
      fixed.push_back(i % cols == 0 ? 1 : 0);
      if (fixed.back()) continue;
      unknown_of[i] = static_cast<int>(node_of.size());
      node_of.push_back(i);
    }
    std::vector<Eigen::Triplet<double, int>> entries;
    for (int u = 0; u < static_cast<int>(node_of.size()); ++u) entries.emplace_back(u, u, kMass);
    for (const TestSpring& s : cotton_flag_springs(rows, cols)) {
      const double k = h * h * s.ks;
      const int a = unknown_of[s.first], b = unknown_of[s.second];
      if (a >= 0) entries.emplace_back(a, a, k);
      if (b >= 0) entries.emplace_back(b, b, k);
      if (a >= 0 && b >= 0) entries.emplace_back(std::min(a, b), std::max(a, b), -k);
    }
    upper.resize(static_cast<int>(node_of.size()), static_cast<int>(node_of.size()));
    upper.setFromTriplets(entries.begin(), entries.end());
  }

  MultigridGlobalSolve solver(double tolerance, long max_cycles = 200) const {
    return MultigridGlobalSolve(builtin::plan_levels(rows, cols, builtin::kDefaultCoarsestNodes),
                                fixed, node_of, builtin::kDefaultMultigridSweeps, tolerance,
                                max_cycles, 1);
  }

  // A right-hand side of uniform entries in [-1, 1], n x 3 row-major.
  std::vector<double> rhs(unsigned seed) const {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<double> out(3 * node_of.size());
    for (double& value : out) value = uniform(random);
    return out;
  }

  uint32_t rows, cols;
  std::vector<uint8_t> fixed;
  std::vector<uint32_t> node_of;
  Matrix upper;
};

// x = A^-1 b by Eigen's own SimplicialLDLT, column by column: the independent solution.
std::vector<double> direct_solve(const Matrix& upper, const std::vector<double>& b) {
  Eigen::SimplicialLDLT<Matrix, Eigen::Upper> ldlt(upper);
  EXPECT_EQ(ldlt.info(), Eigen::Success);
  const auto n = upper.rows();
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> rhs(b.data(), n, 3);
  const Eigen::Matrix<double, Eigen::Dynamic, 3> solution = ldlt.solve(Eigen::MatrixXd(rhs));
  std::vector<double> out(b.size());
  for (Eigen::Index u = 0; u < n; ++u)
    for (Eigen::Index k = 0; k < 3; ++k) out[static_cast<size_t>(3 * u + k)] = solution(u, k);
  return out;
}

double norm(const std::vector<double>& v) {
  double sum = 0.0;
  for (double value : v) sum += value * value;
  return std::sqrt(sum);
}

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  double sum = 0.0;
  for (size_t k = 0; k < a.size(); ++k) sum += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(sum);
}

// A = M + h^2 K with K positive semidefinite has no eigenvalue below the mass, so a residual
// r = b - A x bounds the error: |x - A^-1 b| <= |r| / m <= tolerance |b| / m.
TEST(ProjectiveDynamicsMultigrid, SolvesAsSimplicialLdltToTheTolerance) {
  const double h = 1.0 / 60.0;
  const FlagSystem flag(21, 26, h);
  const std::vector<double> b = flag.rhs(3);
  const std::vector<double> exact = direct_solve(flag.upper, b);
  const std::vector<double> zero(b.size(), 0.0);
  for (const double tolerance : {1e-6, 1e-10}) {
    MultigridGlobalSolve solver = flag.solver(tolerance);
    ASSERT_EQ(solver.factorize(flag.upper), "");
    std::vector<double> x(b.size(), 0.0);
    const MultigridGlobalSolve::Outcome outcome = solver.solve(b.data(), zero.data(), x.data());
    EXPECT_TRUE(outcome.converged) << outcome.residual;
    EXPECT_LE(outcome.residual, tolerance);
    const double bound = tolerance * norm(b) / FlagSystem::kMass;
    EXPECT_LE(distance(x, exact), bound) << tolerance;
    // The bound is not vacuous: it is below the solution's own size.
    EXPECT_LT(bound, 1e-2 * norm(exact)) << tolerance;

    // The comparison can fail: the system of a step 1e-3 longer solves measurably apart.
    const FlagSystem nearby(21, 26, h * (1 + 1e-3));
    EXPECT_GT(distance(direct_solve(nearby.upper, b), exact), bound) << tolerance;
  }
}

// Warm-started from the answer, a solve takes no cycle; from the answer to a nearby right-hand
// side (as a local/global iteration starts from the last), at most half the cycles from zero.
TEST(ProjectiveDynamicsMultigrid, AGoodGuessSavesCycles) {
  const FlagSystem flag(33, 33, 1.0 / 60.0);
  const std::vector<double> b = flag.rhs(4), zero(b.size(), 0.0);
  MultigridGlobalSolve solver = flag.solver(1e-8);
  ASSERT_EQ(solver.factorize(flag.upper), "");
  std::vector<double> x(b.size(), 0.0);
  const long from_zero = solver.solve(b.data(), zero.data(), x.data()).cycles;
  const std::vector<double> solution = x;
  EXPECT_EQ(solver.solve(b.data(), zero.data(), x.data()).cycles, 0);
  std::vector<double> perturbed = b;
  for (size_t k = 0; k < perturbed.size(); k += 7) perturbed[k] *= 1 + 1e-6;
  x = solution;
  const long near = solver.solve(perturbed.data(), zero.data(), x.data()).cycles;
  EXPECT_GT(near, 0);
  EXPECT_LE(2 * near, from_zero) << near << " vs " << from_zero;
}

// The cycles to 1e-6 from zero stay within 1.5x as the grid's side grows 4x; a smoother-only
// solve (one level: Gauss-Seidel sweeps and the dense solve never reached) would grow with the
// side squared.
TEST(ProjectiveDynamicsMultigrid, CyclesStayBoundedAsTheGridGrows) {
  std::vector<long> cycles;
  for (const uint32_t side : {17u, 33u, 65u}) {
    const FlagSystem flag(side, side, 1.0 / 60.0);
    MultigridGlobalSolve solver = flag.solver(1e-6);
    ASSERT_EQ(solver.factorize(flag.upper), "");
    EXPECT_GE(solver.level_count(), 2u);
    const std::vector<double> b = flag.rhs(5), zero(b.size(), 0.0);
    std::vector<double> x(b.size(), 0.0);
    const MultigridGlobalSolve::Outcome outcome = solver.solve(b.data(), zero.data(), x.data());
    ASSERT_TRUE(outcome.converged) << side << ": " << outcome.residual;
    cycles.push_back(outcome.cycles);
  }
  const auto [low, high] = std::minmax_element(cycles.begin(), cycles.end());
  EXPECT_LE(*high, 1.5 * *low) << cycles[0] << " " << cycles[1] << " " << cycles[2];
  EXPECT_LT(*high, 30) << cycles[0] << " " << cycles[1] << " " << cycles[2];
}

// The tolerance is relative to b - A origin: the same system translated by t (x + t solves
// A y = b + A t) and solved from origin t takes the same cycles to the same solution plus t,
// where relative to |b| the translated solve would stop after fewer cycles, far less exact.
TEST(ProjectiveDynamicsMultigrid, ATranslatedSystemSolvesAlike) {
  const FlagSystem flag(33, 33, 1.0 / 60.0);
  const std::vector<double> b = flag.rhs(6), zero(b.size(), 0.0);
  MultigridGlobalSolve solver = flag.solver(1e-8);
  ASSERT_EQ(solver.factorize(flag.upper), "");
  std::vector<double> x(b.size(), 0.0);
  const MultigridGlobalSolve::Outcome at_origin = solver.solve(b.data(), zero.data(), x.data());

  const double translation[3] = {50.0, -20.0, 30.0};
  std::vector<double> t(b.size());
  for (size_t k = 0; k < t.size(); ++k) t[k] = translation[k % 3];
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> t_rows(
      t.data(), flag.upper.rows(), 3);
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> at =
      flag.upper.selfadjointView<Eigen::Upper>() * t_rows;
  std::vector<double> moved_b(b.size()), y = t;
  for (size_t k = 0; k < b.size(); ++k) moved_b[k] = b[k] + at.data()[k];
  const MultigridGlobalSolve::Outcome moved = solver.solve(moved_b.data(), t.data(), y.data());
  EXPECT_EQ(moved.cycles, at_origin.cycles);
  for (size_t k = 0; k < y.size(); ++k) y[k] -= t[k];
  EXPECT_LT(distance(y, x), 1e-9 * norm(x));
}

TEST(ProjectiveDynamicsMultigrid, AMatrixReachingBeyondTwoSpacingsIsRefused) {
  FlagSystem flag(9, 9, 1.0 / 60.0);
  flag.upper.coeffRef(0, 3) = -1.0;  // node 1 to node 4: three columns apart
  MultigridGlobalSolve solver = flag.solver(1e-6);
  EXPECT_EQ(solver.factorize(flag.upper),
            "multigrid: the matrix couples grid nodes 1 and 4, more than 2 grid spacings apart");
}

// ---------------------------------------------------------------- through the plugin

// The flag of flag_springs, pinned along its left column, hanging tilted out of its plane so
// that gravity stretches and bends it from the first step; offered as a grid unless told not.
struct GridFlag {
  GridFlag(uint32_t rows, uint32_t cols, bool on_grid = true)
      : host(rows * cols, left_column(rows, cols), cotton_flag_springs(rows, cols), {0, -9.81, 0}) {
    for (uint32_t r = 0; r < rows; ++r)
      for (uint32_t c = 0; c < cols; ++c)
        host.system().set_position(r * cols + c,
                                   {kSpacing * c, -kSpacing * r, 0.005 * c * c * kSpacing});
    if (on_grid) host.set_grid(rows, cols, kSpacing, {});
  }
  SpringHost<double> host;
};

// Coarsening the 9 x 12 flag while it has more than 12 particles: 9 x 12, 5 x 7, 3 x 4 (with
// the default 256 it would be one level, a dense direct solve).
constexpr double kSmallCoarsest = 12;

std::vector<Vec3> run_flag(double factorization, double tolerance, int steps) {
  constexpr uint32_t kRows = 9, kCols = 12;
  GridFlag flag(kRows, kCols);
  Integrator integrator("projective_dynamics");
  integrator.with("factorization", factorization)
      .with("multigrid_tolerance", tolerance)
      .with("multigrid_coarsest", kSmallCoarsest);
  integrator.start(flag.host.system());
  for (int n = 0; n < steps; ++n) {
    EXPECT_EQ(integrator.step(flag.host.system(), n / 240.0, 1.0 / 240.0), CLOTHLAB_OK)
        << integrator.message();
    EXPECT_EQ(solver_statistics_of(integrator).converged, 1u) << "step " << n;
  }
  std::vector<Vec3> state;
  for (uint32_t i = 0; i < kRows * kCols; ++i) {
    state.push_back(flag.host.system().position(i));
    state.push_back(flag.host.system().velocity(i));
  }
  return state;
}

// 30 steps, each 10 local/global iterations: the multigrid path follows the LDLT path, closer
// the tighter its tolerance (the no-allocation check is the mock host's, on every step).
TEST(ProjectiveDynamicsMultigrid, StepsTheFlagAsTheLdltPath) {
  const std::vector<Vec3> ldlt = run_flag(0, 1e-6, 30), start = run_flag(0, 1e-6, 0);
  const double loose = largest_difference(run_flag(2, 1e-4, 30), ldlt);
  const double tight = largest_difference(run_flag(2, 1e-10, 30), ldlt);
  EXPECT_GT(largest_difference(ldlt, start), 1e-3);  // the flag moved
  EXPECT_LT(tight, 1e-8) << loose;
  EXPECT_LT(tight, loose) << tight << " vs " << loose;
}

TEST(ProjectiveDynamicsMultigrid, ASolveThatMissesItsToleranceIsReported) {
  GridFlag flag(9, 12);
  Integrator integrator("projective_dynamics");
  integrator.with("factorization", 2)
      .with("multigrid_tolerance", 1e-14)
      .with("multigrid_max_cycles", 1)
      .with("multigrid_coarsest", kSmallCoarsest);
  integrator.start(flag.host.system());
  ASSERT_EQ(integrator.step(flag.host.system(), 0.0, 1.0 / 60.0), CLOTHLAB_OK)
      << integrator.message();
  EXPECT_EQ(solver_statistics_of(integrator).converged, 0u);
}

// The message of an integrator that `create`s or `prepare`s with the given settings; empty
// if both succeed.
std::string refusal(GridFlag& flag, const std::vector<std::pair<std::string, double>>& settings) {
  Integrator integrator("projective_dynamics");
  integrator.with("factorization", 2);
  for (const auto& [name, value] : settings) integrator.with(name, value);
  if (integrator.create() != CLOTHLAB_OK) return integrator.message();
  if (integrator.prepare(flag.host.system()) != CLOTHLAB_OK) return integrator.message();
  return {};
}

TEST(ProjectiveDynamicsMultigrid, BadSettingsAreOneLineErrors) {
  GridFlag flag(9, 12);
  EXPECT_EQ(refusal(flag, {}), "");
  EXPECT_EQ(refusal(flag, {{"multigrid_tolerance", 0.0}}),
            "parameter multigrid_tolerance = 0 is outside [1e-14, 0.10000000000000001]");
  EXPECT_EQ(refusal(flag, {{"multigrid_tolerance", 0.5}}),
            "parameter multigrid_tolerance = 0.5 is outside [1e-14, 0.10000000000000001]");
  EXPECT_EQ(refusal(flag, {{"multigrid_coarsest", 0.0}}),
            "parameter multigrid_coarsest = 0 is outside [1, 1024]");
  EXPECT_EQ(refusal(flag, {{"multigrid_coarsest", 5000.0}}),
            "parameter multigrid_coarsest = 5000 is outside [1, 1024]");
  EXPECT_EQ(refusal(flag, {{"factorization", 3.0}}),
            "parameter factorization = 3 is outside [0, 2]");
  GridFlag strip(2, 600);
  EXPECT_EQ(
      refusal(strip, {}),
      "factorization = 2: the 2 x 600 grid coarsens to no fewer than 2 x 600 particles (a side "
      "needs 3 to coarsen); the direct solve there takes at most 1024");
  GridFlag loose(6, 6, false);
  EXPECT_EQ(refusal(loose, {}),
            "factorization = 2 needs a cloth laid out as a grid (clothlab.grid/1); this scene is "
            "not one");
}

TEST(ProjectiveDynamicsMultigrid, ANonPositiveDefiniteMatrixIsAOneLineError) {
  // One spring of the flag with a negative stiffness strong enough that A is indefinite.
  std::vector<TestSpring> springs = cotton_flag_springs(5, 5);
  springs[7].ks = -1e7;
  SpringHost<double> host(25, left_column(5, 5), springs, {0, -9.81, 0});
  for (uint32_t i = 0; i < 25; ++i)
    host.system().set_position(i, {kSpacing * (i % 5), -kSpacing * (i / 5), 0});
  host.set_grid(5, 5, kSpacing, {});
  Integrator integrator("projective_dynamics");
  integrator.with("factorization", 2);
  integrator.start(host.system());
  EXPECT_EQ(integrator.step(host.system(), 0.0, 0.01), CLOTHLAB_ERROR_NUMERICAL);
  const std::string message = integrator.message();
  EXPECT_NE(message.find("not positive definite"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

}  // namespace
}  // namespace clothlab::test
