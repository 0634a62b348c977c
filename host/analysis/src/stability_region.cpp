#include "clothlab/analysis/stability_region.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

namespace clothlab::analysis {
namespace {

using Complex = std::complex<double>;

// Round-off allowance on |amplification| <= 1.
constexpr double kRadiusSlack = 8.0 * std::numeric_limits<double>::epsilon();

bool is_runge_kutta(Method method) {
  return method == Method::ExplicitEuler || method == Method::Midpoint ||
         method == Method::RungeKutta4;
}

// Spectral radius of a real 2x2 matrix from its trace and determinant.
double radius_2x2(double trace, double determinant) {
  const Complex root = std::sqrt(Complex(trace * trace / 4.0 - determinant, 0.0));
  return std::max(std::abs(trace / 2.0 + root), std::abs(trace / 2.0 - root));
}

// Roots of s^2 + c s + w^2 = 0: the mode's eigenvalues as a first-order system.
std::pair<Complex, Complex> mode_eigenvalues(const DampedMode& mode) {
  const Complex root =
      std::sqrt(Complex(mode.damping_rate * mode.damping_rate / 4.0 - mode.omega_squared, 0.0));
  return {-mode.damping_rate / 2.0 + root, -mode.damping_rate / 2.0 - root};
}

// First loss of stability of radius(dt) <= 1, scanning up from time_scale * 1e-6.
double first_unstable_dt(const std::function<double(double)>& radius, double time_scale) {
  if (!(time_scale > 0.0) || !std::isfinite(time_scale)) {
    return std::numeric_limits<double>::infinity();
  }
  auto stable = [&](double dt) { return radius(dt) <= 1.0 + kRadiusSlack; };
  constexpr double kScanRatio = 1.01;
  double dt_stable = 0.0;
  double dt = time_scale * 1e-6;
  const double dt_end = time_scale * 1e3;
  while (stable(dt)) {
    dt_stable = dt;
    dt *= kScanRatio;
    if (dt > dt_end) return std::numeric_limits<double>::infinity();
  }
  if (dt_stable == 0.0) return 0.0;
  double dt_unstable = dt;
  while (dt_unstable - dt_stable > 1e-10 * dt_stable) {
    const double middle = 0.5 * (dt_stable + dt_unstable);
    (stable(middle) ? dt_stable : dt_unstable) = middle;
  }
  return dt_stable;
}

}  // namespace

const char* to_string(Method method) {
  switch (method) {
    case Method::ExplicitEuler:
      return "explicit-euler";
    case Method::SymplecticEuler:
      return "symplectic-euler";
    case Method::Midpoint:
      return "midpoint";
    case Method::RungeKutta4:
      return "rk4";
    case Method::PositionVerlet:
      return "position-verlet";
  }
  return "unknown";
}

double VerletDamping::retention(double dt) const {
  return per_step_fraction > 0.0 ? 1.0 - per_step_fraction : std::exp(-rate_per_s * dt);
}

Complex stability_polynomial(Method method, Complex z) {
  switch (method) {
    case Method::ExplicitEuler:
      return 1.0 + z;
    case Method::Midpoint:
      return 1.0 + z + z * z / 2.0;
    case Method::RungeKutta4:
      return 1.0 + z * (1.0 + z / 2.0 * (1.0 + z / 3.0 * (1.0 + z / 4.0)));
    default:
      throw std::invalid_argument(std::string("stability polynomial: ") + to_string(method) +
                                  " is not a Runge-Kutta method");
  }
}

double amplification_radius(Method method, const DampedMode& mode, double dt,
                            const VerletDamping& verlet) {
  const double h2w2 = dt * dt * mode.omega_squared;
  switch (method) {
    case Method::SymplecticEuler: {
      // (x, v) -> v' = (1 - h c) v - h w^2 x; x' = x + h v'.
      const double velocity_keep = 1.0 - dt * mode.damping_rate;
      return radius_2x2(2.0 - dt * mode.damping_rate - h2w2, velocity_keep);
    }
    case Method::PositionVerlet: {
      // e' = (1 + d - h^2 w^2) e - d e_prev.
      const double d = verlet.retention(dt);
      return radius_2x2(1.0 + d - h2w2, d);
    }
    default: {
      const auto [first, second] = mode_eigenvalues(mode);
      return std::max(std::abs(stability_polynomial(method, first * dt)),
                      std::abs(stability_polynomial(method, second * dt)));
    }
  }
}

double predicted_dt_max(Method method, const DampedMode& mode, const VerletDamping& verlet) {
  const double rate = std::max(std::sqrt(std::max(mode.omega_squared, 0.0)),
                               method == Method::PositionVerlet ? 0.0 : mode.damping_rate);
  return first_unstable_dt(
      [&](double dt) { return amplification_radius(method, mode, dt, verlet); }, 1.0 / rate);
}

double predicted_dt_max(Method method, Complex eigenvalue) {
  if (!is_runge_kutta(method)) {
    throw std::invalid_argument(std::string("stability prediction: ") + to_string(method) +
                                " needs a damped mode, not a single eigenvalue");
  }
  return first_unstable_dt(
      [&](double dt) { return std::abs(stability_polynomial(method, eigenvalue * dt)); },
      1.0 / std::abs(eigenvalue));
}

uint32_t RknTable::evaluations_per_step() const {
  return first_same_as_last && stages > 1 ? stages - 1 : stages;
}

RknTable rkn_table(const clothlab_explicit_scheme& declared) {
  const clothlab_rkn_scheme* scheme = declared.scheme;
  if (scheme == nullptr || scheme->stages < 1 || scheme->stages > CLOTHLAB_RKN_MAX_STAGES ||
      !scheme->c || !scheme->alpha || !scheme->x_coupling || !scheme->v_coupling ||
      !scheme->x_weights || !scheme->v_weights) {
    throw std::invalid_argument("explicit scheme: the table is missing or has " +
                                std::to_string(scheme ? scheme->stages : 0) +
                                " stages (allowed 1 .. 8, every array set)");
  }
  const uint32_t s = scheme->stages;
  RknTable table;
  table.stages = s;
  table.c.assign(scheme->c, scheme->c + s);
  table.alpha.assign(scheme->alpha, scheme->alpha + s);
  table.x_coupling.assign(scheme->x_coupling, scheme->x_coupling + s * s);
  table.v_coupling.assign(scheme->v_coupling, scheme->v_coupling + s * s);
  table.x_weights.assign(scheme->x_weights, scheme->x_weights + s);
  table.v_weights.assign(scheme->v_weights, scheme->v_weights + s);
  table.first_same_as_last = declared.first_same_as_last != 0;
  return table;
}

std::array<double, 4> amplification_matrix(const RknTable& table, const DampedMode& mode, double dt,
                                           bool velocity_forces) {
  const uint32_t s = table.stages;
  const double damping = velocity_forces ? mode.damping_rate : 0.0;
  // The step is linear in (x, v): its columns are the images of (1, 0) and (0, 1).
  std::array<double, 4> matrix{};
  for (int column = 0; column < 2; ++column) {
    const double x = column == 0 ? 1.0 : 0.0, v = column == 0 ? 0.0 : 1.0;
    std::array<double, CLOTHLAB_RKN_MAX_STAGES> a{};
    double x_next = x + dt * v, v_next = v;
    for (uint32_t i = 0; i < s; ++i) {
      double stage_x = x + dt * table.alpha[i] * v, stage_v = v;
      for (uint32_t j = 0; j < i; ++j) {
        stage_x += dt * dt * table.x_coupling[i * s + j] * a[j];
        stage_v += dt * table.v_coupling[i * s + j] * a[j];
      }
      a[i] = -mode.omega_squared * stage_x - damping * stage_v;
      x_next += dt * dt * table.x_weights[i] * a[i];
      v_next += dt * table.v_weights[i] * a[i];
    }
    matrix[column] = x_next;
    matrix[2 + column] = v_next;
  }
  return matrix;
}

double amplification_radius(const RknTable& table, const DampedMode& mode, double dt,
                            bool velocity_forces) {
  const std::array<double, 4> m = amplification_matrix(table, mode, dt, velocity_forces);
  return radius_2x2(m[0] + m[3], m[0] * m[3] - m[1] * m[2]);
}

double predicted_dt_max(const RknTable& table, const DampedMode& mode, bool velocity_forces) {
  const double rate = std::max(std::sqrt(std::max(mode.omega_squared, 0.0)),
                               velocity_forces ? mode.damping_rate : 0.0);
  return first_unstable_dt(
      [&](double dt) { return amplification_radius(table, mode, dt, velocity_forces); },
      1.0 / rate);
}

}  // namespace clothlab::analysis
