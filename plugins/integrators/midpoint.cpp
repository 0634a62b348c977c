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

#include "fused_rkn_integrator.hpp"

namespace clothlab::builtin {

//                                                  c          alpha      x coupling
inline constexpr sdk::RknScheme<2> explicit_midpoint{{0.0, 0.5},
                                                     {0.0, 0.5},
                                                     {0.0, 0.0, 0.0, 0.0},
                                                     // v coupling   x weights   v weights
                                                     {0.0, 0.0, 0.5, 0.0},
                                                     {0.5, 0.0},
                                                     {0.0, 1.0}};

struct ExplicitMidpoint : FusedRknIntegrator<explicit_midpoint> {
  static constexpr const char* id = "midpoint";
  static constexpr const char* name = "Explicit midpoint (RK2)";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Explicit midpoint Runge-Kutta on (x, v); second order, two force evaluations";
  static constexpr uint32_t order = 2;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit ExplicitMidpoint(const sdk::Params&) {}
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-midpoint", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ExplicitMidpoint>,
                      clothlab::sdk::scenarios<>)
