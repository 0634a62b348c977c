// Faulty: a second integrator copied from the first keeps its id; descriptor.ids-unique catches
// it (a host could not tell the two apart).
#include "symplectic_euler.hpp"

struct First : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "duplicated-euler";
  static constexpr const char* name = "Symplectic Euler";
  static constexpr const char* description = "the original";
};

struct CopiedFromFirst : First {
  using First::First;
  static constexpr const char* name = "Symplectic Euler, half steps";
  static constexpr const char* description = "faulty: a copy that kept the first one's id";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    First::step(system, t, dt / 2);
    First::step(system, t + dt / 2, dt / 2);
  }
};

using BothIntegrators = clothlab::sdk::integrators<First, CopiedFromFirst>;
CLOTHLAB_PLUGIN_ENTRY("faulty-duplicates-an-id", "0.0.1", BothIntegrators,
                      clothlab::sdk::scenarios<>)
