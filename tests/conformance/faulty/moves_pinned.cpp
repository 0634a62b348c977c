// Faulty: nudges pinned particles by a rounding-sized step (numerics.pinned-* catch it:
// pins must stay bit-for-bit unchanged).
#include "symplectic_euler.hpp"

struct MovesPinned : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "moves-pinned";
  static constexpr const char* name = "Symplectic Euler that moves pins";
  static constexpr const char* description = "faulty: pinned particles drift by 1e-6 m per step";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    for (uint32_t i = 0; i < system.particle_count(); ++i)
      if (system.inverse_mass()[i] == Real(0)) system.x()[i] += Real(1e-6);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-moves-pinned", "0.0.1", clothlab::sdk::integrators<MovesPinned>,
                      clothlab::sdk::scenarios<>)
