// projective_dynamics' two factorisations of its constant matrix (parameter `factorization`):
// CHOLMOD's supernodal LL^T against Eigen's SimplicialLDLT, as solvers (the headers) and as
// the plugin's step, and a matrix that is not positive definite refused in one line.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "cholmod_factorization.hpp"
#include "integrator_harness.hpp"
#include "simplicial_ldlt_factorization.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

using Matrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// Positions and velocities after `steps` steps of the flag, hanging in its plane and
// tilted, so that gravity stretches and bends it from the first step.
std::vector<Vec3> run_flag(double factorization, int steps) {
  constexpr uint32_t kRows = 9, kCols = 12;
  SpringHost<double> host(kRows * kCols, left_column(kRows, kCols),
                          provot_net_springs(kRows, kCols, 0.02, 6000.0, 60.0, 0.02),
                          {0, -9.81, 0});
  for (uint32_t r = 0; r < kRows; ++r)
    for (uint32_t c = 0; c < kCols; ++c)
      host.system().set_position(r * kCols + c, {0.02 * c, -0.02 * r, 0.005 * c * c * 0.02});
  Integrator integrator("projective_dynamics");
  integrator.with("factorization", factorization);
  integrator.start(host.system());
  integrator.run(host.system(), steps, 1.0 / 240.0);
  std::vector<Vec3> state;
  for (uint32_t i = 0; i < kRows * kCols; ++i) {
    state.push_back(host.system().position(i));
    state.push_back(host.system().velocity(i));
  }
  return state;
}

TEST(ProjectiveDynamicsFactorization, CholmodAndLdltStepTheFlagAlike) {
  const std::vector<Vec3> ldlt = run_flag(0, 30), cholmod = run_flag(1, 30);
  const std::vector<Vec3> start = run_flag(0, 0);
  // The flag moved (so the comparison compares motion), and both agree to rounding.
  EXPECT_GT(largest_difference(ldlt, start), 1e-3);
  EXPECT_LT(largest_difference(ldlt, cholmod), 1e-12);
}

// M + h^2 K for the flag's springs with unit masses, upper triangle (the plugin's form).
Matrix flag_matrix(uint32_t rows, uint32_t cols, double h) {
  std::vector<Eigen::Triplet<double, int>> entries;
  for (uint32_t i = 0; i < rows * cols; ++i) entries.emplace_back(i, i, 0.01);
  for (const TestSpring& s : provot_net_springs(rows, cols, 0.02, 6000.0, 60.0, 0.02)) {
    const double k = h * h * s.ks;
    entries.emplace_back(s.first, s.first, k);
    entries.emplace_back(s.second, s.second, k);
    entries.emplace_back(s.first, s.second, -k);
  }
  Matrix upper(rows * cols, rows * cols);
  upper.setFromTriplets(entries.begin(), entries.end());
  return upper;
}

// The largest |a - b| relative to the largest |a|.
double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double difference = 0.0, scale = 0.0;
  for (size_t k = 0; k < a.size(); ++k) {
    difference = std::max(difference, std::abs(a[k] - b[k]));
    scale = std::max(scale, std::abs(a[k]));
  }
  return difference / scale;
}

TEST(ProjectiveDynamicsFactorization, CholmodSolvesAsSimplicialLdltTo1e10) {
  const double h = 1.0 / 60.0;
  const Matrix upper = flag_matrix(20, 30, h);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> rhs(3 * static_cast<size_t>(upper.rows()));
  for (double& value : rhs) value = uniform(random);

  builtin::SimplicialLdltFactorization ldlt;
  builtin::CholmodFactorization cholmod;
  ldlt.analyze(upper);
  cholmod.analyze(upper);
  ASSERT_EQ(ldlt.factorize(upper), "");
  ASSERT_EQ(cholmod.factorize(upper), "");
  std::vector<double> by_ldlt = rhs, by_cholmod = rhs;
  ldlt.solve_in_place(by_ldlt.data());
  cholmod.solve_in_place(by_cholmod.data());
  EXPECT_LT(relative_difference(by_ldlt, by_cholmod), 1e-10);
  // The solution solves the system (A x = b, A from its upper triangle).
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> x(by_cholmod.data(),
                                                                                upper.rows(), 3),
      b(rhs.data(), upper.rows(), 3);
  const Eigen::MatrixXd residual = upper.selfadjointView<Eigen::Upper>() * x - b;
  EXPECT_LT(residual.cwiseAbs().maxCoeff(), 1e-12);

  // The comparison can fail: the matrix of a step 1e-6 longer solves measurably apart.
  const Matrix nearby = flag_matrix(20, 30, h * (1 + 1e-6));
  ASSERT_EQ(cholmod.factorize(nearby), "");
  std::vector<double> by_nearby = rhs;
  cholmod.solve_in_place(by_nearby.data());
  EXPECT_GT(relative_difference(by_ldlt, by_nearby), 1e-10);
}

TEST(ProjectiveDynamicsFactorization, ANonPositiveDefiniteMatrixIsAOneLineError) {
  for (const double factorization : {0.0, 1.0}) {
    // A spring of negative stiffness strong enough that M + h^2 K is indefinite.
    const std::vector<TestSpring> springs = {{0, 1, 0.3, 1e3, 0.0}, {1, 2, 0.3, -1e6, 0.0}};
    SpringHost<double> host(3, {0}, springs, {0, -9.81, 0});
    for (uint32_t i = 0; i < 3; ++i) host.system().set_position(i, {0.3 * i, 0, 0});
    Integrator integrator("projective_dynamics");
    integrator.with("factorization", factorization);
    integrator.start(host.system());
    EXPECT_EQ(integrator.step(host.system(), 0.0, 0.01), CLOTHLAB_ERROR_NUMERICAL)
        << "factorization " << factorization;
    const std::string message = integrator.message();
    EXPECT_NE(message.find("not positive definite"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace clothlab::test
