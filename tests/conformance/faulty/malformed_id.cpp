// Faulty: its id is the display name in CamelCase, not an id ([a-z0-9_-]+); descriptor.fields
// catches it (ids are what configs and --param name).
#include "symplectic_euler.hpp"

struct MalformedId : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "SymplecticEuler";
  static constexpr const char* name = "Symplectic Euler with a malformed id";
  static constexpr const char* description = "faulty: the id has capitals";
};

CLOTHLAB_PLUGIN_ENTRY("faulty-malformed-id", "0.0.1", clothlab::sdk::integrators<MalformedId>,
                      clothlab::sdk::scenarios<>)
