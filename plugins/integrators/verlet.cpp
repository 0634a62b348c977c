// Position (Störmer) Verlet with velocity damping, after seed eq. 2.19:
//   x_{n+1} = x_n + f (x_n - x_{n-1}) + beta a(t_n, x_n)
// kept in displacement form, d_n = x_{n+1} - x_n (fewer rounding errors than 2x - x_prev):
//   d_n = f d_{n-1} + beta a_n,   x_{n+1} = x_n + d_n.
//
// Damping. By default `damping` is a rate c (1/s): f = exp(-c dt), so the dynamics do not
// depend on dt and approximate x'' = a - c x'. Then beta = dt (1 - f) / c, the exact
// displacement weight of a constant force under that drag; with plain dt^2 (the seed's
// form) the method would drop to first order whenever c > 0. `damping_per_step` p > 0
// reproduces the seed literally: f = 1 - p, beta = dt^2 (dt-dependent dynamics).
//
// Default rate 0.1 1/s: a 10 s velocity time constant, so a 2 s run keeps > 80 % of its
// motion (close to the undamped physics the other integrators see), yet long runs settle.
// The integrator never passes velocities to the force evaluation, so the host builds no
// spring-damping stage; the rate is the only dissipation.
//
// Start and restart (first step, after prepare, or when dt changes): the history is
// rebuilt from (x, v) by the Taylor expansion backwards,
//   d_{-1} = x_0 - x_{-1} = dt v_0 - dt^2/2 (a_0 - c v_0),
// which keeps the first step second-order accurate.
//
// Velocity. The host reads v for energy and output, so after each step v holds the
// second-order estimate v_{n+1} = d_n / dt + dt/2 (a_n - c d_n / dt) (exact for
// free fall); it is never read back by the integration itself, except to restart.
#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

struct StormerVerlet {
  static constexpr const char* id = "verlet";
  static constexpr const char* name = "Position (Stormer) Verlet with damping";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Seed eq. 2.19: x += f (x - x_prev) + beta a(x); second order, one force evaluation, "
      "no velocity-dependent forces";
  static constexpr uint32_t order = 2;
  static constexpr uint32_t evals_per_step = 1;
  static constexpr uint32_t flags = 0;
  static constexpr std::array<clothlab_param_spec, 2> params{
      sdk::real_param("damping", 0.1, 0.0, 1.0e4, "1/s",
                      "velocity damping rate c: f = exp(-c dt) (used unless damping_per_step > 0)"),
      sdk::real_param("damping_per_step", 0.0, 0.0, 0.5, "",
                      "seed-style damping per step p: f = 1 - p, dt-dependent (seed: 0.005)"),
  };

  explicit StormerVerlet(const sdk::Params& values)
      : damping_rate_(values.real("damping")), damping_per_step_(values.real("damping_per_step")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    scratch_.allocate(system);
    history_dt_ = 0.0;
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [acceleration, displacement, zero] = scratch_.bind(system);
    if (dt == 0.0) return;
    Real* x = system.x();
    Real* v = system.v();
    const Coefficients k = coefficients(dt);

    system.acceleration(t, x, nullptr, acceleration);
    if (dt != history_dt_) {
      // d_{-1} = dt v - dt^2/2 a + c dt^2/2 v; `zero` is never written, so it serves as
      // the base of a plain linear combination.
      system.template lincomb<2>(displacement, zero, {dt + 0.5 * k.rate * dt * dt, -0.5 * dt * dt},
                                 {v, acceleration});
      history_dt_ = dt;
    }
    system.template lincomb<2>(displacement, zero, {k.f, k.beta}, {displacement, acceleration});
    system.axpy(x, 1.0, displacement);
    system.template lincomb<2>(v, zero, {(1.0 - 0.5 * k.rate * dt) / dt, 0.5 * dt},
                               {displacement, acceleration});
  }

 private:
  struct Coefficients {
    double f;     // factor on the previous displacement
    double beta;  // weight of the acceleration
    double rate;  // effective damping rate c, 1/s
  };

  Coefficients coefficients(double dt) const {
    if (damping_per_step_ > 0.0) {
      const double f = 1.0 - damping_per_step_;
      return {f, dt * dt, -std::log1p(-damping_per_step_) / dt};
    }
    const double z = damping_rate_ * dt;
    // (1 - exp(-z)) / z, which tends to 1 as z -> 0.
    const double weight = z > 0.0 ? -std::expm1(-z) / z : 1.0;
    return {std::exp(-z), dt * dt * weight, damping_rate_};
  }

  double damping_rate_;
  double damping_per_step_;
  double history_dt_ = 0.0;  // dt the displacement history was built with; 0 = none
  ScratchVectors<3> scratch_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-verlet", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::StormerVerlet>,
                      clothlab::sdk::scenarios<>)
