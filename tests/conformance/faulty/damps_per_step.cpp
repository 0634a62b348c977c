// Faulty: applies its drag per step (v *= 1 - 1e-3) instead of per second (v *= 1 - c dt), so
// a step with dt = 0 still slows the cloth; lifecycle.dt-zero catches it.
#include "symplectic_euler.hpp"

struct DampsPerStep : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "damps-per-step";
  static constexpr const char* name = "Symplectic Euler with per-step drag";
  static constexpr const char* description = "faulty: drag does not scale with dt";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    system.axpy(system.v(), -1e-3, system.v());
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-damps-per-step", "0.0.1", clothlab::sdk::integrators<DampsPerStep>,
                      clothlab::sdk::scenarios<>)
