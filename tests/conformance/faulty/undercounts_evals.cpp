// Faulty: declares one force evaluation per step and makes two; lifecycle.evals-per-step
// catches it.
#include "symplectic_euler.hpp"

struct UndercountsEvals : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "undercounts-evals";
  static constexpr const char* name = "Symplectic Euler that evaluates twice";
  static constexpr const char* description = "faulty: two evaluations per step, one declared";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    Real* a = static_cast<Real*>(acceleration_);
    system.acceleration(t, system.x(), system.v(), a);  // wasted: recomputed below
    SymplecticEulerBase::step(system, t, dt);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-undercounts-evals", "0.0.1",
                      clothlab::sdk::integrators<UndercountsEvals>, clothlab::sdk::scenarios<>)
