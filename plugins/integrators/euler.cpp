// Semi-implicit (symplectic) Euler, exactly as the seed writes its "explicit Euler"
// (eq. 2.15, after Provot 1995): the velocity is updated first and the position then
// moves with the NEW velocity. Forward (fully explicit) Euler would use the old one.
//   a = a(t, x, v);  v += dt a;  x += dt v
// As a one-stage Runge-Kutta-Nystrom scheme (x += dt v + dt^2 a, v += dt a) the host runs
// it as one sweep over memory.
#include <array>
#include <clothlab/sdk.hpp>

#include "scratch_vectors.hpp"

namespace clothlab::builtin {

struct SemiImplicitEuler {
  static constexpr const char* id = "euler";
  static constexpr const char* name = "Semi-implicit (symplectic) Euler";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Seed eq. 2.15: v += dt a(x, v), then x += dt v_new; first order, one force evaluation";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 1;
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 0> params{};

  explicit SemiImplicitEuler(const sdk::Params&) {}

  static constexpr sdk::RknScheme<1> scheme{{0.0}, {0.0}, {0.0}, {0.0}, {1.0}, {1.0}};
  // Declared as data: the host derives the cost and the stability limit from the table.
  static constexpr clothlab_rkn_scheme raw_scheme = scheme.raw();
  static constexpr clothlab_explicit_scheme explicit_scheme = sdk::explicit_scheme_of(raw_scheme);

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    prepared_for_.allocate(system);
    system.reserve_rkn(1);
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

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-euler", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::SemiImplicitEuler>,
                      clothlab::sdk::scenarios<>)
