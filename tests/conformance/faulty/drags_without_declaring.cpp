// Faulty: symplectic Euler with a numerical drag towards rest that vanishes with the step
// (v /= 1 + c dt^2 each step, a drag of rate c dt), declaring no CLOTHLAB_TRAIT_DRAGS_TOWARDS_REST.
// Like a first-order method's own damping it keeps the declared order, leaves rest at rest and
// a step of dt = 0 unchanged, so every other check passes; but it takes momentum no force gave,
// which the stability monitor would read as the pins' pull (numerics.momentum catches it).
#include "symplectic_euler.hpp"

struct DragsWithoutDeclaring : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "drags-without-declaring";
  static constexpr const char* name = "Symplectic Euler with an undeclared drag towards rest";
  static constexpr const char* description =
      "faulty: drags towards rest at a rate c dt, declares no drags-towards-rest trait";
  static constexpr double drag = 20.0;  // c, 1/s^2: a drag of 0.02 1/s at dt = 1 ms

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    system.axpy(system.v(), -drag * dt * dt / (1.0 + drag * dt * dt), system.v());
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-drags-without-declaring", "0.0.1",
                      clothlab::sdk::integrators<DragsWithoutDeclaring>, clothlab::sdk::scenarios<>)
