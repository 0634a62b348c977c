// Faulty: symplectic Euler that resolves its contacts at the step's start time t instead of its
// end t + dt: against a still collider it keeps the cloth out, but a moving one is met a step
// behind, where it was, so a blade rising at 95 m/s passes the strip
// (contacts.moving-collider catches it).
#include "symplectic_euler.hpp"

struct ResolvesAtTheStepStart : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "resolves-at-the-step-start";
  static constexpr const char* name = "Symplectic Euler resolving contacts at the step's start";
  static constexpr const char* description =
      "faulty: calls clothlab.contacts/1 with the step's start time";
  static constexpr clothlab_integrator_traits traits = clothlab::faulty::kResolvesContactsTraits;

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    system.resolve_contacts(t);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-resolves-at-the-step-start", "0.0.1",
                      clothlab::sdk::integrators<ResolvesAtTheStepStart>,
                      clothlab::sdk::scenarios<>)
