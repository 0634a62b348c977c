// Chebyshev acceleration of xpbd's sweeps (parameters chebyshev_rho, chebyshev_delay;
// xpbd_chebyshev.hpp): off, the bits are unchanged; on, the same converged substep as the plain
// sweeps, checked independently by its momentum balance; a radius that diverges is an error,
// not a silent result; the parameters' ranges. The grid cloth: xpbd_grid_test.cpp; bitwise
// identity across thread counts: thread_identity_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "integrator_harness.hpp"
#include "spring_host.hpp"

namespace clothlab::test {
namespace {

constexpr double kH = 1.0 / 30.0;

// Particles of 1 kg joined by springs, some pinned, started moving: one substep of h.
struct Net {
  uint32_t count;
  std::vector<uint32_t> pinned;
  std::vector<TestSpring> springs;
  std::vector<Vec3> x0, v0;
};

// A 6 x 8 net of stiff springs hanging from its top row, tilted out of its plane and moving.
Net tilted_net() {
  constexpr uint32_t rows = 6, cols = 8;
  Net net{rows * cols, {}, {}, {}, {}};
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      const uint32_t i = r * cols + c;
      if (r == 0) net.pinned.push_back(i);
      if (c + 1 < cols) net.springs.push_back({i, i + 1, 0.1, 4e3, 1.0});
      if (r + 1 < rows) net.springs.push_back({i, i + cols, 0.1, 4e3, 1.0});
      if (r + 1 < rows && c + 1 < cols)
        net.springs.push_back({i, i + cols + 1, 0.1 * std::sqrt(2.0), 4e3, 1.0});
      net.x0.push_back({0.1 * c, -0.08 * r, 0.06 * r});
      net.v0.push_back({0, 0, 0.5 * r});
    }
  return net;
}

// A vertical chain of 30 stiff springs hanging from its top, stretched and moving along its
// line: every spring's direction stays put, so the converged substep is backward Euler exactly.
Net vertical_chain() {
  constexpr uint32_t count = 31;
  Net net{count, {0}, {}, {}, {}};
  for (uint32_t i = 0; i < count; ++i) {
    if (i + 1 < count) net.springs.push_back({i, i + 1, 0.1, 4e3, 1.0});
    net.x0.push_back({0, -0.1 * i - 0.001 * std::sin(0.7 * i), 0});
    net.v0.push_back({0, 0.3 * std::cos(1.3 * i), 0});
  }
  return net;
}

// The state after one substep with `iterations` sweeps (sequential Gauss-Seidel: the host's
// trivial colouring), or the step's status.
struct NetStep {
  clothlab_status status = CLOTHLAB_OK;
  std::string message;
  std::vector<Vec3> x, v;
};

NetStep one_substep(const Net& net, long iterations, double rho, long delay = 1,
                    bool reversed_order = false) {
  SpringHost<double> host(net.count, net.pinned, net.springs, {0, -g, 0});
  if (reversed_order) {
    std::vector<std::vector<uint32_t>> colors;
    for (auto k = static_cast<uint32_t>(net.springs.size()); k-- > 0;) colors.push_back({k});
    host.set_spring_colors(colors);
  }
  for (uint32_t i = 0; i < net.count; ++i) {
    host.system().set_position(i, net.x0[i]);
    host.system().set_velocity(i, net.v0[i]);
  }
  Integrator xpbd("xpbd");
  xpbd.with("inner_substeps", 1)
      .with("iterations", static_cast<double>(iterations))
      .with("threads", 1);
  xpbd.with("chebyshev_rho", rho).with("chebyshev_delay", static_cast<double>(delay));
  xpbd.start(host.system());
  NetStep result;
  result.status = xpbd.step(host.system(), 0.0, kH);
  result.message = xpbd.message();
  for (uint32_t i = 0; i < net.count; ++i) {
    result.x.push_back(host.system().position(i));
    result.v.push_back(host.system().velocity(i));
  }
  return result;
}

// Where the springs keep their directions, the converged XPBD substep is backward Euler: with
// dx = x - x0 and each spring's multiplier at the root of eq. 26,
// lambda = -(ks h^2 C + kd h n.(dx_i - dx_j)), every free particle balances
// m (dx - h (v0 + h g)) = sum lambda grad C. Largest imbalance over the free particles,
// relative to the largest inertial term. Computed from the state alone, not from the plugin's
// multipliers.
double momentum_residual(const Net& net, const NetStep& step) {
  std::vector<Vec3> imbalance(net.count), inertial(net.count);
  for (uint32_t i = 0; i < net.count; ++i)
    for (int k = 0; k < 3; ++k) {
      const double predicted = kH * (net.v0[i][k] + kH * (k == 1 ? -g : 0.0));
      inertial[i][k] = (step.x[i][k] - net.x0[i][k]) - predicted;
      imbalance[i][k] = inertial[i][k];
    }
  for (const TestSpring& s : net.springs) {
    Vec3 d, moved;
    for (int k = 0; k < 3; ++k) {
      d[k] = step.x[s.first][k] - step.x[s.second][k];
      moved[k] =
          (step.x[s.first][k] - net.x0[s.first][k]) - (step.x[s.second][k] - net.x0[s.second][k]);
    }
    const double length = std::hypot(d[0], d[1], d[2]);
    const double closing = (d[0] * moved[0] + d[1] * moved[1] + d[2] * moved[2]) / length;
    const double lambda = -(s.ks * kH * kH * (length - s.rest_length) + s.kd * kH * closing);
    for (int k = 0; k < 3; ++k) {
      imbalance[s.first][k] -= lambda * d[k] / length;
      imbalance[s.second][k] += lambda * d[k] / length;
    }
  }
  double largest_imbalance = 0.0, largest_inertial = 0.0;
  for (uint32_t i = 0; i < net.count; ++i) {
    if (std::find(net.pinned.begin(), net.pinned.end(), i) != net.pinned.end()) continue;
    for (int k = 0; k < 3; ++k) {
      largest_imbalance = std::max(largest_imbalance, std::abs(imbalance[i][k]));
      largest_inertial = std::max(largest_inertial, std::abs(inertial[i][k]));
    }
  }
  return largest_imbalance / largest_inertial;
}

// The plain sweeps' spectral radius, from their error ratio per sweep.
double plain_radius(const Net& net, const NetStep& converged, long first, long second) {
  const double e1 = largest_difference(one_substep(net, first, 0.0).x, converged.x);
  const double e2 = largest_difference(one_substep(net, second, 0.0).x, converged.x);
  return std::pow(e2 / e1, 1.0 / static_cast<double>(second - first));
}

// The fewest sweeps (of 1..limit) whose substep is within `error` of `converged`.
long sweeps_to(const Net& net, double error, double rho, const NetStep& converged, long limit) {
  for (long n = 1; n <= limit; ++n)
    if (largest_difference(one_substep(net, n, rho, 10).x, converged.x) <= error) return n;
  return limit + 1;
}

// All weights 1 (the delay covers every sweep): the accelerated path must leave the plain
// sweeps' bits alone; so must rho = 0 with any delay.
TEST(XpbdChebyshev, WeightsOfOneLeaveTheBitsUnchanged) {
  const Net net = tilted_net();
  const NetStep plain = one_substep(net, 12, 0.0);
  for (const NetStep& other : {one_substep(net, 12, 0.9, 12), one_substep(net, 12, 0.0, 3)})
    for (uint32_t i = 0; i < net.count; ++i) {
      EXPECT_EQ(std::memcmp(plain.x[i].data(), other.x[i].data(), sizeof(Vec3)), 0) << i;
      EXPECT_EQ(std::memcmp(plain.v[i].data(), other.v[i].data(), sizeof(Vec3)), 0) << i;
    }
}

// The chain: both converge to backward Euler, checked by the momentum balance, and the
// accelerated sweeps get there in fewer iterations (34 against 46 to 1e-8: Gauss-Seidel's
// radius gains less from the extrapolation than a Jacobi-like iteration's, lab/real-cloth.md).
TEST(XpbdChebyshev, ReachesBackwardEulerOnAChainInFewerSweeps) {
  const Net chain = vertical_chain();
  const NetStep converged = one_substep(chain, 100, 0.0);
  ASSERT_EQ(converged.status, CLOTHLAB_OK) << converged.message;
  EXPECT_LT(momentum_residual(chain, converged), 1e-9);
  // An unconverged substep does not pass the balance: the check can fail.
  EXPECT_GT(momentum_residual(chain, one_substep(chain, 3, 0.0)), 1e-3);
  const double rho = plain_radius(chain, converged, 20, 40);
  ASSERT_GT(rho, 0.5) << "a case where the plain sweeps are slow";
  ASSERT_LT(rho, 0.999);
  const NetStep accelerated = one_substep(chain, 100, rho, 10);
  ASSERT_EQ(accelerated.status, CLOTHLAB_OK) << accelerated.message;
  EXPECT_LT(momentum_residual(chain, accelerated), 1e-9) << "rho " << rho;
  const long plain_sweeps = sweeps_to(chain, 1e-8, 0.0, converged, 100);
  const long accelerated_sweeps = sweeps_to(chain, 1e-8, rho, converged, 100);
  RecordProperty("plain_sweeps", static_cast<int>(plain_sweeps));
  RecordProperty("accelerated_sweeps", static_cast<int>(accelerated_sweeps));
  EXPECT_LE(plain_sweeps, 100) << "rho " << rho;
  EXPECT_LT(accelerated_sweeps, plain_sweeps) << "rho " << rho;
}

// The tilted net, whose springs turn within the substep: there the converged XPBD substep
// depends on the path of the sweeps (each projection pushes along its spring's direction of
// the moment), so the plain sweeps in another order converge elsewhere too. The accelerated
// sweeps must land closer to the plain fixed point than that change of order moves it.
TEST(XpbdChebyshev, ReachesThePlainFixedPointOnATurningNet) {
  const Net net = tilted_net();
  const NetStep converged = one_substep(net, 100, 0.0);
  ASSERT_EQ(converged.status, CLOTHLAB_OK) << converged.message;
  const double order_change =
      largest_difference(one_substep(net, 100, 0.0, 1, true).x, converged.x);
  const double rho = plain_radius(net, converged, 20, 40);
  ASSERT_GT(rho, 0.5) << "a case where the plain sweeps are slow";
  ASSERT_LT(rho, 0.999);
  const NetStep accelerated = one_substep(net, 100, rho, 10);
  ASSERT_EQ(accelerated.status, CLOTHLAB_OK) << accelerated.message;
  EXPECT_LT(largest_difference(accelerated.x, converged.x), 0.1 * order_change)
      << "rho " << rho << ", a change of order moves it " << order_change;
}

TEST(XpbdChebyshev, ADivergingRadiusIsAnErrorNamingIt) {
  const NetStep diverged = one_substep(vertical_chain(), 100, 0.9999, 1);
  EXPECT_EQ(diverged.status, CLOTHLAB_ERROR_NUMERICAL);
  EXPECT_NE(diverged.message.find("chebyshev_rho"), std::string::npos) << diverged.message;
  EXPECT_EQ(diverged.message.find('\n'), std::string::npos) << diverged.message;
}

TEST(XpbdChebyshev, RefusesParametersOutOfRange) {
  const std::vector<std::pair<std::string, double>> bad = {{"chebyshev_rho", -0.1},
                                                           {"chebyshev_rho", 1.0},
                                                           {"chebyshev_rho", 2.0},
                                                           {"chebyshev_delay", 0},
                                                           {"chebyshev_delay", 1001}};
  for (const auto& [name, value] : bad) {
    Integrator integrator("xpbd");
    integrator.with(name, value);
    EXPECT_EQ(integrator.create(), CLOTHLAB_ERROR_INVALID_ARGUMENT) << name << " " << value;
    const std::string message = integrator.message();
    EXPECT_NE(message.find(name), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace clothlab::test
