// Faulty: its constructor refuses substeps = 1 ("substepping needs at least 2"), the schema's
// own default and minimum: a stricter rule than the schema it declares. params.defaults
// catches it.
#include "substeps_euler.hpp"

struct RefusesItsDefault : clothlab::faulty::SubstepsEulerBase {
  explicit RefusesItsDefault(const clothlab::sdk::Params& values) : SubstepsEulerBase(values) {
    if (substeps_ < 2)
      throw clothlab::sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT,
                                 "substeps = 1: substepping needs at least 2");
  }
  static constexpr const char* id = "refuses-its-default";
  static constexpr const char* name = "Symplectic Euler refusing its default substeps";
  static constexpr const char* description = "faulty: create refuses the default value";
};

CLOTHLAB_PLUGIN_ENTRY("faulty-refuses-its-default", "0.0.1",
                      clothlab::sdk::integrators<RefusesItsDefault>, clothlab::sdk::scenarios<>)
