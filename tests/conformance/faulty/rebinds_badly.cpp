// Faulty: after a second prepare it steps with half the step size (a stale setting carried
// over from the first binding); lifecycle.prepare-twice catches it.
#include "symplectic_euler.hpp"

struct RebindsBadly : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "rebinds-badly";
  static constexpr const char* name = "Symplectic Euler that mishandles a second prepare";
  static constexpr const char* description = "faulty: a second prepare halves every later step";

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    ++prepared_;
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, prepared_ > 1 ? dt / 2 : dt);
  }

  int prepared_ = 0;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-rebinds-badly", "0.0.1", clothlab::sdk::integrators<RebindsBadly>,
                      clothlab::sdk::scenarios<>)
