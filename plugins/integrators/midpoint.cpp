// Explicit midpoint method (second-order Runge-Kutta) on the coupled first-order system
// d/dt (x, v) = (v, a(t, x, v)) — the textbook form; seed eq. 2.16 drops the position half.
//   a1 = a(t, x, v)
//   x_mid = x + dt/2 v,   v_mid = v + dt/2 a1
//   a2 = a(t + dt/2, x_mid, v_mid)
//   x += dt v_mid,        v += dt a2
// With v_mid substituted, x += dt v + dt^2/2 a1: a two-stage Runge-Kutta-Nystrom scheme,
// which the host runs as one sweep over memory.
#include <array>
#include <clothlab/sdk.hpp>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

struct ExplicitMidpoint {
  static constexpr const char* id = "midpoint";
  static constexpr const char* name = "Explicit midpoint (RK2)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Explicit midpoint Runge-Kutta on (x, v); second order, two force evaluations";
  static constexpr uint32_t order = 2;
  static constexpr uint32_t evals_per_step = 2;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit ExplicitMidpoint(const sdk::Params&) {}

  //                                        c          alpha      x coupling
  static constexpr sdk::RknScheme<2> scheme{{0.0, 0.5},
                                            {0.0, 0.5},
                                            {0.0, 0.0, 0.0, 0.0},
                                            // v coupling   x weights   v weights
                                            {0.0, 0.0, 0.5, 0.0},
                                            {0.5, 0.0},
                                            {0.0, 1.0}};
  // Declared as data: the host derives the cost and the stability limit from the table.
  static constexpr clothlab_rkn_scheme raw_scheme = scheme.raw();
  static constexpr clothlab_explicit_scheme explicit_scheme = sdk::explicit_scheme_of(raw_scheme);

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    prepared_for_.allocate(system);
    system.reserve_rkn(2);
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    (void)prepared_for_.bind(system);
    if (dt == 0.0) return;
    system.step_rkn(t, dt, scheme);
  }

 private:
  ScratchVectors<0> prepared_for_;  // no vectors: remembers the system
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-midpoint", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ExplicitMidpoint>,
                      clothlab::sdk::scenarios<>)
