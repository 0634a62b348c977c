// Semi-implicit (symplectic) Euler, exactly as the seed writes its "explicit Euler"
// (eq. 2.15, after Provot 1995): the velocity is updated first and the position then
// moves with the NEW velocity. Forward (fully explicit) Euler would use the old one.
//   a = a(t, x, v);  v += dt a;  x += dt v
// As a one-stage Runge-Kutta-Nystrom scheme (x += dt v + dt^2 a, v += dt a) the host runs
// it as one sweep over memory.
#include <array>
#include <clothlab/sdk.hpp>

#include "fused_rkn_integrator.hpp"

namespace clothlab::builtin {

//                                                    c      alpha  x, v coupling  x, v weights
inline constexpr sdk::RknScheme<1> semi_implicit_euler{{0.0}, {0.0}, {0.0}, {0.0}, {1.0}, {1.0}};

struct SemiImplicitEuler : FusedRknIntegrator<semi_implicit_euler> {
  static constexpr const char* id = "euler";
  static constexpr const char* name = "Semi-implicit (symplectic) Euler";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Seed eq. 2.15: v += dt a(x, v), then x += dt v_new; first order, one force evaluation";
  static constexpr uint32_t order = 1;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit SemiImplicitEuler(const sdk::Params&) {}
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-euler", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::SemiImplicitEuler>,
                      clothlab::sdk::scenarios<>)
