// Faulty: writes NaN into the state on every step (every check that steps sees it).
#include <limits>

#include "symplectic_euler.hpp"

struct ProducesNan : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "produces-nan";
  static constexpr const char* name = "Symplectic Euler that emits NaN";
  static constexpr const char* description = "faulty: the first active x becomes NaN";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    if (dt > 0 && !system.active().empty())
      system.x()[system.active()[0].begin] = std::numeric_limits<Real>::quiet_NaN();
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-produces-nan", "0.0.1", clothlab::sdk::integrators<ProducesNan>,
                      clothlab::sdk::scenarios<>)
