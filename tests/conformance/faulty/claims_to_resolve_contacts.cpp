// Faulty: symplectic Euler declaring CLOTHLAB_TRAIT_RESOLVES_CONTACTS that never asks the host to
// resolve them: a fast strip falls through a thin capsule (contacts.no-tunnelling catches it).
#include "symplectic_euler.hpp"

struct ClaimsToResolveContacts : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "claims-to-resolve-contacts";
  static constexpr const char* name = "Symplectic Euler claiming to resolve contacts";
  static constexpr const char* description =
      "faulty: declares that it resolves contacts, never calls clothlab.contacts/1";
  static constexpr clothlab_integrator_traits traits = clothlab::faulty::kResolvesContactsTraits;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-claims-to-resolve-contacts", "0.0.1",
                      clothlab::sdk::integrators<ClaimsToResolveContacts>,
                      clothlab::sdk::scenarios<>)
