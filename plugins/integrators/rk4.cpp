// Classic fourth-order Runge-Kutta on the coupled first-order system
// d/dt (x, v) = (v, a(t, x, v)) — the textbook form (seed eq. 2.17 has typos in k1, k4).
//   stage 1: x1 = x,            v1 = v,            a1 = a(t,        x1, v1)
//   stage 2: x2 = x + h/2 v1,   v2 = v + h/2 a1,   a2 = a(t + h/2,  x2, v2)
//   stage 3: x3 = x + h/2 v2,   v3 = v + h/2 a2,   a3 = a(t + h/2,  x3, v3)
//   stage 4: x4 = x + h v3,     v4 = v + h a3,     a4 = a(t + h,    x4, v4)
//   x += h/6 (v1 + 2 v2 + 2 v3 + v4),   v += h/6 (a1 + 2 a2 + 2 a3 + a4)
// Substituting the stage velocities, every stage state is x, v and the a_i:
//   x3 = x + h/2 v + h^2/4 a1,  x4 = x + h v + h^2/2 a2,  x += h v + h^2/6 (a1 + a2 + a3),
// a four-stage Runge-Kutta-Nystrom scheme, which the host runs as one sweep over memory.
#include <array>
#include <clothlab/sdk.hpp>

#include "fused_rkn_integrator.hpp"

namespace clothlab::builtin {

inline constexpr double sixth = 1.0 / 6.0, third = 1.0 / 3.0;
inline constexpr sdk::RknScheme<4> classic_rk4{
    {0.0, 0.5, 0.5, 1.0},  // c
    {0.0, 0.5, 0.5, 1.0},  // alpha
    {0.0, 0.0, 0.0, 0.0,   // x coupling: X3 gets h^2/4 a1, X4 h^2/2 a2
     0.0, 0.0, 0.0, 0.0,   //
     0.25, 0.0, 0.0, 0.0,  //
     0.0, 0.5, 0.0, 0.0},
    {0.0, 0.0, 0.0, 0.0,  // v coupling: V2 = v + h/2 a1, V3 = v + h/2 a2, V4 = v + h a3
     0.5, 0.0, 0.0, 0.0,  //
     0.0, 0.5, 0.0, 0.0,  //
     0.0, 0.0, 1.0, 0.0},
    {sixth, sixth, sixth, 0.0},     // x weights
    {sixth, third, third, sixth}};  // v weights

struct ClassicRungeKutta4 : FusedRknIntegrator<classic_rk4> {
  static constexpr const char* id = "rk4";
  static constexpr const char* name = "Classic Runge-Kutta (RK4)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Classic fourth-order Runge-Kutta on (x, v); fourth order, four force evaluations";
  static constexpr uint32_t order = 4;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit ClassicRungeKutta4(const sdk::Params&) {}
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-rk4", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ClassicRungeKutta4>,
                      clothlab::sdk::scenarios<>)
