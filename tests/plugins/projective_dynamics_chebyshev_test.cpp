// Chebyshev acceleration of projective_dynamics' local/global iterations (parameter
// chebyshev_rho; chebyshev_weights.hpp): the weights' closed-form limit, the same fixed point as
// the plain iteration, fewer iterations to an error where the radius is estimated right, and
// the parameter's range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "chebyshev_weights.hpp"
#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

// omega_{k+1} = 4 / (4 - rho^2 omega_k) has the fixed point 2 / (1 + sqrt(1 - rho^2)); the
// first `delay` weights are 1 and the next 2 / (2 - rho^2).
TEST(ChebyshevWeights, FollowWangsScheduleToItsLimit) {
  for (const double rho : {0.5, 0.9, 0.99}) {
    builtin::ChebyshevWeights weights(rho, 3);
    weights.restart();
    for (int k = 0; k < 3; ++k) EXPECT_EQ(weights.next(), 1.0);
    EXPECT_DOUBLE_EQ(weights.next(), 2.0 / (2.0 - rho * rho));
    double omega = 0.0;
    for (int k = 0; k < 2000; ++k) omega = weights.next();
    EXPECT_NEAR(omega, 2.0 / (1.0 + std::sqrt(1.0 - rho * rho)), 1e-12) << "rho " << rho;
  }
  builtin::ChebyshevWeights off(0.0, 1);
  off.restart();
  for (int k = 0; k < 5; ++k) EXPECT_EQ(off.next(), 1.0);
}

// A 6 x 8 net of stiff springs (1 kg particles) hanging from its top row, tilted out of its
// plane; positions after one step of `iterations` local/global iterations.
std::vector<Vec3> one_step(long iterations, double rho) {
  constexpr uint32_t kRows = 6, kCols = 8;
  std::vector<TestSpring> springs;
  std::vector<uint32_t> pinned;
  for (uint32_t r = 0; r < kRows; ++r)
    for (uint32_t c = 0; c < kCols; ++c) {
      const uint32_t i = r * kCols + c;
      if (r == 0) pinned.push_back(i);
      if (c + 1 < kCols) springs.push_back({i, i + 1, 0.1, 4e3, 1.0});
      if (r + 1 < kRows) springs.push_back({i, i + kCols, 0.1, 4e3, 1.0});
      if (r + 1 < kRows && c + 1 < kCols)
        springs.push_back({i, i + kCols + 1, 0.1 * std::sqrt(2.0), 4e3, 1.0});
    }
  SpringHost<double> host(kRows * kCols, pinned, springs, {0, -9.81, 0});
  for (uint32_t i = 0; i < kRows * kCols; ++i) {
    const double r = i / kCols, c = i % kCols;
    host.system().set_position(i, {0.1 * c, -0.08 * r, 0.06 * r});
    host.system().set_velocity(i, {0, 0, 0.5 * r});
  }
  Integrator integrator("projective_dynamics");
  integrator.with("iterations", static_cast<double>(iterations)).with("chebyshev_rho", rho);
  integrator.start(host.system());
  integrator.run(host.system(), 1, 1.0 / 30.0);
  std::vector<Vec3> positions;
  for (uint32_t i = 0; i < kRows * kCols; ++i) positions.push_back(host.system().position(i));
  return positions;
}

// The fewest iterations (of 1..limit) whose step is within `error` of `converged`.
long iterations_to(double error, double rho, const std::vector<Vec3>& converged, long limit) {
  for (long n = 1; n <= limit; ++n)
    if (largest_difference(one_step(n, rho), converged) <= error) return n;
  return limit + 1;
}

TEST(ProjectiveDynamicsChebyshev, ReachesThePlainFixedPointInFewerIterations) {
  const std::vector<Vec3> converged = one_step(1000, 0.0);
  // The plain iteration's spectral radius, from its error ratio per iteration.
  const double e20 = largest_difference(one_step(20, 0.0), converged);
  const double e40 = largest_difference(one_step(40, 0.0), converged);
  const double rho = std::pow(e40 / e20, 1.0 / 20.0);
  ASSERT_GT(rho, 0.5) << "a case where the plain iteration is slow";
  ASSERT_LT(rho, 0.999);
  // The same fixed point.
  EXPECT_LT(largest_difference(one_step(1000, rho), converged), 1e-12) << "rho " << rho;
  const long plain = iterations_to(1e-8, 0.0, converged, 400);
  const long accelerated = iterations_to(1e-8, rho, converged, 400);
  EXPECT_LE(plain, 400) << "rho " << rho;
  EXPECT_LT(2 * accelerated, plain) << "rho " << rho;
}

TEST(ProjectiveDynamicsChebyshev, RefusesARadiusOutsideZeroToOne) {
  for (const double rho : {-0.1, 1.0, 2.0}) {
    Integrator integrator("projective_dynamics");
    integrator.with("chebyshev_rho", rho);
    EXPECT_EQ(integrator.create(), CLOTHLAB_ERROR_INVALID_ARGUMENT) << rho;
    const std::string message = integrator.message();
    EXPECT_NE(message.find("chebyshev_rho"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace clothlab::test
