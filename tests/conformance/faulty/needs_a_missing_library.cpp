// Faulty: calls a helper from a library it was never linked with, and is built without
// --no-undefined (a plain add_library, not clothlab_add_plugin), so the link succeeded and
// dlopen with RTLD_NOW fails; loading.dlopen catches it.
#include "symplectic_euler.hpp"

extern "C" double clothlab_faulty_helper_never_linked(double);

struct NeedsAMissingLibrary : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "needs-a-missing-library";
  static constexpr const char* name = "Symplectic Euler with an unresolved symbol";
  static constexpr const char* description = "faulty: depends on a symbol nothing defines";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, clothlab_faulty_helper_never_linked(dt));
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-needs-a-missing-library", "0.0.1",
                      clothlab::sdk::integrators<NeedsAMissingLibrary>, clothlab::sdk::scenarios<>)
