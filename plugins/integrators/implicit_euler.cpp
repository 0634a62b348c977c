// Linearised backward Euler (Baraff & Witkin 1998). Backward Euler on (x, v),
//   v1 = v0 + h a(x1, v1),   x1 = x0 + h v1,
// is the equation g(dv) = h a(x0 + h (v0 + dv), v0 + dv) - dv = 0 for dv = v1 - v0. Baraff and
// Witkin take one Newton step from dv = 0 with a linearised about (x0, v0):
//   (I - h da/dv - h^2 da/dx) dv = h (a0 + h (da/dx) v0)
// (their (M - h df/dv - h^2 df/dx) dv = h (f0 + h (df/dx) v0) divided by M). `newton_steps`
// > 1 continues with Newton on g itself, which converges to backward Euler proper. First order;
// stable at any dt on a damped cloth. The Newton steps, their CG solves and the settings are
// implicit_step_solver.hpp's, shared with bdf2.
#include <clothlab/ext/integrator_traits.h>
#include <clothlab/ext/solver_statistics.h>

#include <array>
#include <clothlab/sdk.hpp>

#include "implicit_step_solver.hpp"

namespace clothlab::builtin {

struct ImplicitEuler {
  static constexpr const char* id = "implicit_euler";
  static constexpr const char* name = "Implicit (backward) Euler, Baraff-Witkin";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Linearised backward Euler (Baraff & Witkin 1998), Newton steps solved by block-Jacobi "
      "preconditioned CG on Jacobian products; first order, unconditionally stable";
  static constexpr uint32_t order = 1;
  static constexpr uint32_t evals_per_step = 1;  // one more per Newton step beyond the first
  static constexpr uint32_t flags = CLOTHLAB_INTEGRATOR_USES_VELOCITY_FORCES;
  static constexpr std::array<clothlab_param_spec, 10> params = implicit_step_solver_params(
      "Newton steps per time step: 1 = Baraff-Witkin, more converge to backward Euler on the "
      "nonlinear springs");
  static constexpr clothlab_integrator_traits traits = implicit_step_solver_traits;

  explicit ImplicitEuler(const sdk::Params& values) : solver_(values) {}

  template <class Real>
  void prepare(sdk::System<Real>& system) {
    solver_.prepare(system);
  }

  template <class Real>
  void step(sdk::System<Real>& system, double t, double h) {
    solver_.begin_step();
    if (h == 0.0) return;
    Real* x = system.x();
    Real* v = system.v();
    // Backward Euler holds the attached particles where they are at the step's end: the solve
    // linearises about that state (the products ignore pinned entries, so a pin's motion reaches
    // its neighbours only through the positions the forces are evaluated at).
    system.move_attachments(t + h);
    const Real* dv = solver_.solve(system, t, t + h, h, x, v, FirstNewtonStep::kAtStart);
    system.axpy(v, 1.0, dv);
    system.axpy(x, h, v);
    // After the solve: contacts change v, and the warm start's dv stays the solver's.
    system.resolve_contacts(t + h);
  }

  void last_step_statistics(clothlab_solver_step_statistics& out) const {
    solver_.last_step_statistics(out);
  }

 private:
  ImplicitStepSolver solver_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-implicit-euler", "1.0.0",
                      clothlab::sdk::integrators<clothlab::builtin::ImplicitEuler>,
                      clothlab::sdk::scenarios<>)
