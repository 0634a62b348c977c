// Stability limits derived from declared Runge-Kutta-Nystrom tables (any plugin's
// clothlab.explicit-scheme/1) against the closed forms: symplectic Euler and velocity Verlet
// w h <= 2, RK4 on the imaginary axis |w h| <= 2 sqrt 2, a 3-stage Kutta table sqrt 3, and the
// damped limits of the classic methods.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "clothlab/analysis/stability_region.hpp"

namespace clothlab::analysis {
namespace {

constexpr double kOmega = 40.0;  // rad/s
const DampedMode kUndamped{kOmega * kOmega, 0.0};

// The RKN form of an explicit Runge-Kutta method (A, b, c) applied to (x, v), as plugin.h
// states it: alpha = c, x coupling A^2, v coupling A, x weights b A, v weights b.
RknTable from_runge_kutta(const std::vector<std::vector<double>>& a, const std::vector<double>& b) {
  const auto s = static_cast<uint32_t>(b.size());
  RknTable table;
  table.stages = s;
  table.x_coupling.assign(s * s, 0.0);
  table.v_coupling.assign(s * s, 0.0);
  table.x_weights.assign(s, 0.0);
  for (uint32_t i = 0; i < s; ++i) {
    double c = 0;
    for (uint32_t j = 0; j < s; ++j) {
      c += a[i][j];
      table.v_coupling[i * s + j] = a[i][j];
      for (uint32_t k = 0; k < s; ++k) table.x_coupling[i * s + j] += a[i][k] * a[k][j];
      table.x_weights[j] += b[i] * a[i][j];
    }
    table.c.push_back(c);
    table.alpha.push_back(c);
  }
  table.v_weights = b;
  return table;
}

RknTable symplectic_euler() {
  RknTable table;
  table.stages = 1;
  table.c = table.alpha = table.x_coupling = table.v_coupling = {0.0};
  table.x_weights = table.v_weights = {1.0};
  return table;
}

RknTable velocity_verlet() {
  RknTable table;
  table.stages = 2;
  table.c = table.alpha = {0.0, 1.0};
  table.x_coupling = {0.0, 0.0, 0.5, 0.0};
  table.v_coupling = {0.0, 0.0, 1.0, 0.0};
  table.x_weights = {0.5, 0.0};
  table.v_weights = {0.5, 0.5};
  table.first_same_as_last = true;
  return table;
}

RknTable rk4() {
  return from_runge_kutta({{0, 0, 0, 0}, {0.5, 0, 0, 0}, {0, 0.5, 0, 0}, {0, 0, 1, 0}},
                          {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6});
}

RknTable kutta3() {
  return from_runge_kutta({{0, 0, 0}, {0.5, 0, 0}, {-1, 2, 0}}, {1.0 / 6, 2.0 / 3, 1.0 / 6});
}

RknTable midpoint() { return from_runge_kutta({{0, 0}, {0.5, 0}}, {0.0, 1.0}); }

TEST(DeclaredScheme, UndampedLimitsOnTheImaginaryAxis) {
  EXPECT_NEAR(predicted_dt_max(symplectic_euler(), kUndamped, true) * kOmega, 2.0, 1e-6);
  EXPECT_NEAR(predicted_dt_max(velocity_verlet(), kUndamped, false) * kOmega, 2.0, 1e-6);
  EXPECT_NEAR(predicted_dt_max(rk4(), kUndamped, true) * kOmega, 2.0 * std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(predicted_dt_max(kutta3(), kUndamped, true) * kOmega, std::sqrt(3.0), 1e-6);
}

TEST(DeclaredScheme, DampedLimitsMatchTheClosedForms) {
  for (const double c : {0.5, 6.0, 30.0}) {
    const DampedMode mode{kOmega * kOmega, c};
    EXPECT_NEAR(predicted_dt_max(symplectic_euler(), mode, true),
                predicted_dt_max(Method::SymplecticEuler, mode), 1e-9)
        << c;
    EXPECT_NEAR(predicted_dt_max(midpoint(), mode, true), predicted_dt_max(Method::Midpoint, mode),
                1e-9)
        << c;
    EXPECT_NEAR(predicted_dt_max(rk4(), mode, true), predicted_dt_max(Method::RungeKutta4, mode),
                1e-9)
        << c;
  }
}

TEST(DeclaredScheme, WithoutVelocityForcesTheDampingIsNotSeen) {
  const DampedMode damped{kOmega * kOmega, 30.0};
  EXPECT_EQ(predicted_dt_max(velocity_verlet(), damped, false),
            predicted_dt_max(velocity_verlet(), kUndamped, false));
}

TEST(DeclaredScheme, SymplecticEulersMatrixIsTheHandOne) {
  const double h = 1e-3, c = 6.0;
  const std::array<double, 4> m =
      amplification_matrix(symplectic_euler(), DampedMode{kOmega * kOmega, c}, h, true);
  // v' = (1 - h c) v - h w^2 x; x' = x + h v'.
  const double w2 = kOmega * kOmega;
  EXPECT_NEAR(m[0], 1.0 - h * h * w2, 1e-15);
  EXPECT_NEAR(m[1], h * (1.0 - h * c), 1e-15);
  EXPECT_NEAR(m[2], -h * w2, 1e-15);
  EXPECT_NEAR(m[3], 1.0 - h * c, 1e-15);
}

TEST(DeclaredScheme, EvaluationsPerStepCountFirstSameAsLast) {
  EXPECT_EQ(symplectic_euler().evaluations_per_step(), 1u);
  EXPECT_EQ(velocity_verlet().evaluations_per_step(), 1u);
  EXPECT_EQ(kutta3().evaluations_per_step(), 3u);
  EXPECT_EQ(rk4().evaluations_per_step(), 4u);
}

TEST(DeclaredScheme, AMalformedTableIsRefused) {
  const clothlab_explicit_scheme missing{sizeof(clothlab_explicit_scheme), 0, nullptr};
  EXPECT_THROW(rkn_table(missing), std::invalid_argument);
  const double zero[1] = {0.0};
  const clothlab_rkn_scheme no_stages{
      sizeof(clothlab_rkn_scheme), 0, zero, zero, zero, zero, zero, zero};
  const clothlab_explicit_scheme empty{sizeof(clothlab_explicit_scheme), 0, &no_stages};
  EXPECT_THROW(rkn_table(empty), std::invalid_argument);
}

}  // namespace
}  // namespace clothlab::analysis
