// Faulty: symplectic Euler that lets the contacts move its particles but keeps the velocity it
// had before them: the cloth stays out of a body, but a body sliding under it never carries it
// (contacts.carried-by-a-moving-body catches it).
#include "symplectic_euler.hpp"

struct KeepsItsVelocityThroughContacts
    : clothlab::faulty::ContactsAroundEulerBase<KeepsItsVelocityThroughContacts> {
  using ContactsAroundEulerBase::ContactsAroundEulerBase;
  static constexpr const char* id = "keeps-its-velocity-through-contacts";
  static constexpr const char* name = "Symplectic Euler ignoring the contacts' velocity";
  static constexpr const char* description =
      "faulty: restores its velocity after clothlab.contacts/1";

  template <class Real>
  static const Real* kept(clothlab::sdk::System<Real>& system) {
    return system.v();
  }

  template <class Real>
  void after_contacts(clothlab::sdk::System<Real>& system, const Real* velocity_before) {
    system.copy(system.v(), velocity_before);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-keeps-its-velocity-through-contacts", "0.0.1",
                      clothlab::sdk::integrators<KeepsItsVelocityThroughContacts>,
                      clothlab::sdk::scenarios<>)
