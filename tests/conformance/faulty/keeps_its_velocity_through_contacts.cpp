// Faulty: symplectic Euler that lets the contacts move its particles but keeps the velocity it
// had before them: the cloth stays out of a body, but a body sliding under it never carries it
// (contacts.carried-by-a-moving-body catches it).
#include "symplectic_euler.hpp"

struct KeepsItsVelocityThroughContacts : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "keeps-its-velocity-through-contacts";
  static constexpr const char* name = "Symplectic Euler ignoring the contacts' velocity";
  static constexpr const char* description =
      "faulty: restores its velocity after clothlab.contacts/1";
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits), CLOTHLAB_TRAIT_RESOLVES_CONTACTS, nullptr, nullptr};

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    velocity_ = system.alloc_vector();
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, dt);
    Real* const kept = static_cast<Real*>(velocity_);
    system.copy(kept, system.v());
    system.resolve_contacts(t + dt);
    system.copy(system.v(), kept);
  }

  void* velocity_ = nullptr;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-keeps-its-velocity-through-contacts", "0.0.1",
                      clothlab::sdk::integrators<KeepsItsVelocityThroughContacts>,
                      clothlab::sdk::scenarios<>)
