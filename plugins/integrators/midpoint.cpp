// Explicit midpoint method (second-order Runge-Kutta) on the coupled first-order system
// d/dt (x, v) = (v, a(t, x, v)) — the textbook form; seed eq. 2.16 drops the position half.
//   a1 = a(t, x, v)
//   x_mid = x + dt/2 v,   v_mid = v + dt/2 a1
//   a2 = a(t + dt/2, x_mid, v_mid)
//   x += dt v_mid,        v += dt a2
// With v_mid substituted, x += dt v + dt^2/2 a1: the midpoint state is formed inside the
// force pass (acceleration_at) and only the two accelerations are stored.
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

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    scratch_.allocate(system);
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const auto [a1, a2] = scratch_.bind(system);
    if (dt == 0.0) return;
    Real* x = system.x();
    Real* v = system.v();
    const double half = 0.5 * dt;

    system.acceleration(t, x, v, a1);
    system.acceleration_at(t + half, sdk::Sum<Real, 1>{x, {half}, {v}},
                           sdk::Sum<Real, 1>{v, {half}, {a1}}, a2);
    system.template lincomb<2>(x, x, {dt, half * dt}, {v, a1});
    system.axpy(v, dt, a2);
  }

 private:
  ScratchVectors<2> scratch_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-midpoint", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ExplicitMidpoint>,
                      clothlab::sdk::scenarios<>)
