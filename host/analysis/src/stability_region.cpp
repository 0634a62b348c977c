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

Method method_for_plugin(const char* integrator_id) {
  const std::string id = integrator_id ? integrator_id : "";
  if (id == "euler") return Method::SymplecticEuler;
  if (id == "forward-euler" || id == "explicit-euler") return Method::ExplicitEuler;
  if (id == "midpoint") return Method::Midpoint;
  if (id == "rk4") return Method::RungeKutta4;
  if (id == "verlet") return Method::PositionVerlet;
  throw std::invalid_argument("stability prediction: integrator '" + id +
                              "' has no known stability region (known: euler, forward-euler, "
                              "midpoint, rk4, verlet)");
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

}  // namespace clothlab::analysis
