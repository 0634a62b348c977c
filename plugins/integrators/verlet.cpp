// Position (Störmer) Verlet with velocity damping, after seed eq. 2.19:
//   x_{n+1} = x_n + f (x_n - x_{n-1}) + beta a(t_n, x_n)
// kept in displacement form, d_n = x_{n+1} - x_n (fewer rounding errors than 2x - x_prev):
//   d_n = f d_{n-1} + beta a_n,   x_{n+1} = x_n + d_n.
//
// Damping. By default `damping` is a rate c (1/s): f = exp(-c dt), so the dynamics do not
// depend on dt and approximate x'' = a - c x'. Then beta = dt (1 - f) / c, the exact
// displacement weight of a constant force under that drag; with plain dt^2 (the seed's
// form) the method would drop to first order whenever c > 0. `damping_per_step` p > 0
// reproduces the seed literally: f = 1 - p, beta = dt^2 (dt-dependent dynamics), with the
// equivalent rate c = -ln(1 - p) / dt used below.
//
// Default rate 0: the drag is a force no other integrator applies and no conformance reference
// knows, so by default Verlet integrates the model's ODE (less its spring damping: the
// integrator never passes velocities to the force evaluation, so the host builds no
// spring-damping stage; the rate is its only dissipation, set it to let long runs settle).
//
// Start, restart and velocity use the solution of x'' = a - c x' for a constant a over one
// step (z = c dt, w = (1 - e^{-z}) / z, phi = (e^z - 1) / z), so free fall with drag is
// reproduced exactly. The first step (after prepare, or when dt changes) has no history and
// takes its displacement from (x, v) instead:
//   d_0 = dt w v_0 + dt^2 (1 - w) / z a_0                    (dt v_0 + dt^2/2 a_0 at c = 0)
// After each step v holds the velocity the host reads for energy and output (the
// integration itself reads v only to restart):
//   v_{n+1} = d_n / (dt phi) + dt (1 - 1 / phi) / z a_n       (d_n / dt + dt/2 a_n at c = 0)
//
// Contacts: not resolved (no CLOTHLAB_TRAIT_RESOLVES_CONTACTS; the host refuses scenes with
// colliders). The state that carries the motion is the displacement history d, not v: a contact
// would have to rewrite d consistently with the velocity it changes, which this form has no
// inverse for short of restarting the history every step (a different, first-order method).
// Attachments: moved to their targets after the step (clothlab.attachment-targets/1).
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
      sdk::real_param("damping", 0.0, 0.0, 1.0e4, "1/s",
                      "velocity damping rate c: f = exp(-c dt) (used unless damping_per_step > 0)"),
      sdk::real_param("damping_per_step", 0.0, 0.0, 0.5, "",
                      "seed-style damping per step p: f = 1 - p, dt-dependent (seed: 0.005)"),
  };

  // Undamped position Verlet is velocity Verlet on (x, v): the same positions, so the same
  // stability. Declared as a two-stage table whose last acceleration is the next step's
  // first, one evaluation per step: x += h v + h^2/2 a(x), v += h/2 (a(x) + a(x_new)).
  static constexpr sdk::RknScheme<2> velocity_verlet{
      {0.0, 1.0}, {0.0, 1.0}, {0.0, 0.0, 0.5, 0.0}, {0.0, 0.0, 1.0, 0.0}, {0.5, 0.0}, {0.5, 0.5}};
  static constexpr clothlab_rkn_scheme raw_scheme = velocity_verlet.raw();
  static constexpr clothlab_explicit_scheme explicit_scheme =
      sdk::explicit_scheme_of(raw_scheme, true);
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits),
      CLOTHLAB_TRAIT_MOVES_ATTACHMENTS | CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST, nullptr, nullptr};

  explicit StormerVerlet(const sdk::Params& values)
      : damping_rate_(values.real("damping")), damping_per_step_(values.real("damping_per_step")) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    scratch_.allocate(system);
    history_dt_ = 0.0;
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [acceleration, displacement] = scratch_.bind(system);
    if (dt == 0.0) return;
    Real* x = system.x();
    Real* v = system.v();
    const Coefficients k = coefficients(dt);

    system.acceleration(t, x, nullptr, acceleration);
    // Each sum starts from a vector it reads anyway instead of a zero vector, one stream less:
    // f d = d + (f - 1) d and velocity_d d = d + (velocity_d - 1) d, where f - 1 also keeps
    // its precision when the coefficients round to float; on a restart d - d is an exact 0.
    if (dt != history_dt_) {
      system.template lincomb<3>(displacement, displacement, {-1.0, k.start_v, k.start_a},
                                 {displacement, v, acceleration});
      history_dt_ = dt;
    } else {
      system.template lincomb<2>(displacement, displacement, {k.f_minus_one, k.beta},
                                 {displacement, acceleration});
    }
    system.axpy(x, 1.0, displacement);
    system.template lincomb<2>(v, displacement, {k.velocity_d - 1.0, k.velocity_a},
                               {displacement, acceleration});
    // The step's one evaluation saw the attachments at its start; the history d holds only
    // free particles, so moving the pinned ones leaves it consistent.
    system.move_attachments(t + dt);
  }

 private:
  struct Coefficients {
    double f_minus_one, beta;       // d_n = f d_{n-1} + beta a_n
    double start_v, start_a;        // d_0 = start_v v_0 + start_a a_0
    double velocity_d, velocity_a;  // v_{n+1} = velocity_d d_n + velocity_a a_n
  };

  Coefficients coefficients(double dt) const {
    const bool per_step = damping_per_step_ > 0.0;
    const double z = per_step ? -std::log1p(-damping_per_step_) : damping_rate_ * dt;
    const double w = z == 0.0 ? 1.0 : -std::expm1(-z) / z;
    // z / (e^z - 1) = 1 / phi; tends to 0 for large z without overflowing to a NaN.
    const double inverse_phi = z == 0.0 ? 1.0 : z / std::expm1(z);
    return {per_step ? -damping_per_step_ : std::expm1(-z),
            per_step ? dt * dt : dt * dt * w,
            dt * w,
            dt * dt * one_minus_w_over_z(z),
            inverse_phi / dt,
            dt * one_minus_inverse_phi_over_z(z)};
  }

  // (1 - w) / z = 1/2 - z/6 + z^2/24 - ...; the series avoids cancellation at small z.
  static double one_minus_w_over_z(double z) {
    if (z < 1e-2) return 0.5 - z * (1.0 / 6 - z * (1.0 / 24 - z * (1.0 / 120 - z / 720)));
    return (1.0 + std::expm1(-z) / z) / z;
  }

  // (1 - 1 / phi) / z = 1/2 - z/12 + z^3/720 - ... (z / (e^z - 1) is the Bernoulli series).
  static double one_minus_inverse_phi_over_z(double z) {
    if (z < 1e-2) return 0.5 - z / 12 + z * z * z / 720;
    return (1.0 - z / std::expm1(z)) / z;
  }

  double damping_rate_;
  double damping_per_step_;
  double history_dt_ = 0.0;  // dt the displacement history was built with; 0 = none
  ScratchVectors<2> scratch_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-verlet", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::StormerVerlet>,
                      clothlab::sdk::scenarios<>)
