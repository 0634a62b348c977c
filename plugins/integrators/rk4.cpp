// Classic fourth-order Runge-Kutta on the coupled first-order system
// d/dt (x, v) = (v, a(t, x, v)) — the textbook form (seed eq. 2.17 has typos in k1, k4).
//   stage 1: x1 = x,            v1 = v,            a1 = a(t,        x1, v1)
//   stage 2: x2 = x + h/2 v1,   v2 = v + h/2 a1,   a2 = a(t + h/2,  x2, v2)
//   stage 3: x3 = x + h/2 v2,   v3 = v + h/2 a2,   a3 = a(t + h/2,  x3, v3)
//   stage 4: x4 = x + h v3,     v4 = v + h a3,     a4 = a(t + h,    x4, v4)
//   x += h/6 (v1 + 2 v2 + 2 v3 + v4),   v += h/6 (a1 + 2 a2 + 2 a3 + a4)
// Substituting the stage velocities, every stage state is x, v and the a_i:
//   x3 = x + h/2 v + h^2/4 a1,  x4 = x + h v + h^2/2 a2,  x += h v + h^2/6 (a1 + a2 + a3),
// so the stage states are formed inside the force pass (acceleration_at) and only the four
// accelerations are stored.
#include <array>
#include <clothlab/sdk.hpp>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

struct ClassicRungeKutta4 {
  static constexpr const char* id = "rk4";
  static constexpr const char* name = "Classic Runge-Kutta (RK4)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Classic fourth-order Runge-Kutta on (x, v); fourth order, four force evaluations";
  static constexpr uint32_t order = 4;
  static constexpr uint32_t evals_per_step = 4;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit ClassicRungeKutta4(const sdk::Params&) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    scratch_.allocate(system);
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double h) {
    const auto [a1, a2, a3, a4] = scratch_.bind(system);
    if (h == 0.0) return;
    Real* x = system.x();
    Real* v = system.v();
    using Sum1 = sdk::Sum<Real, 1>;
    using Sum2 = sdk::Sum<Real, 2>;
    const double half = 0.5 * h, h2 = h * h;

    system.acceleration(t, x, v, a1);
    system.acceleration_at(t + half, Sum1{x, {half}, {v}}, Sum1{v, {half}, {a1}}, a2);
    system.acceleration_at(t + half, Sum2{x, {half, 0.25 * h2}, {v, a1}}, Sum1{v, {half}, {a2}},
                           a3);
    system.acceleration_at(t + h, Sum2{x, {h, 0.5 * h2}, {v, a2}}, Sum1{v, {h}, {a3}}, a4);

    const double sixth = h / 6.0, third = h / 3.0, h2_sixth = h2 / 6.0;
    system.template lincomb<4>(x, x, {h, h2_sixth, h2_sixth, h2_sixth}, {v, a1, a2, a3});
    system.template lincomb<4>(v, v, {sixth, third, third, sixth}, {a1, a2, a3, a4});
  }

 private:
  ScratchVectors<4> scratch_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-rk4", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ClassicRungeKutta4>,
                      clothlab::sdk::scenarios<>)
