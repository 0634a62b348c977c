// Faulty: built with a plain add_library (default visibility, no version script) instead of
// clothlab_add_plugin, so every function it defines is exported beside the entry point and
// may clash with the host's or another plugin's symbols; loading.exports catches it.
#include "symplectic_euler.hpp"

extern "C" double clothlab_faulty_halve(double dt) { return dt / 2; }

struct ExportsItsHelpers : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "exports-its-helpers";
  static constexpr const char* name = "Symplectic Euler exporting its helpers";
  static constexpr const char* description = "faulty: exports more than the entry point";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    SymplecticEulerBase::step(system, t, clothlab_faulty_halve(dt));
    SymplecticEulerBase::step(system, t + clothlab_faulty_halve(dt), clothlab_faulty_halve(dt));
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-exports-its-helpers", "0.0.1",
                      clothlab::sdk::integrators<ExportsItsHelpers>, clothlab::sdk::scenarios<>)
