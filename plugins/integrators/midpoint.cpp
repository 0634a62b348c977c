// Explicit midpoint method (second-order Runge-Kutta) on the coupled first-order system
// d/dt (x, v) = (v, a(t, x, v)) — the textbook form; seed eq. 2.16 drops the position half.
//   a1 = a(t, x, v)
//   x_mid = x + dt/2 v,   v_mid = v + dt/2 a1
//   a2 = a(t + dt/2, x_mid, v_mid)
//   x += dt v_mid,        v += dt a2
#include <array>
#include <clothlab/sdk.hpp>

#include "pinned_state.hpp"
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

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    scratch_.allocate(system);
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [acceleration, x_mid, v_mid] = scratch_.bind(system);
    if (dt == 0.0) return;
    Real* x = system.x();
    Real* v = system.v();
    copy_pinned(system, x_mid, x);
    copy_pinned(system, v_mid, v);

    system.acceleration(t, x, v, acceleration);
    system.template lincomb<1>(x_mid, x, {0.5 * dt}, {v});
    system.template lincomb<1>(v_mid, v, {0.5 * dt}, {acceleration});
    system.acceleration(t + 0.5 * dt, x_mid, v_mid, acceleration);
    system.axpy(x, dt, v_mid);
    system.axpy(v, dt, acceleration);
  }

 private:
  ScratchVectors<3> scratch_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-midpoint", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ExplicitMidpoint>,
                      clothlab::sdk::scenarios<>)
