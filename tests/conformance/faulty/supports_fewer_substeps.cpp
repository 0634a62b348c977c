// Faulty: its schema allows up to 64 substeps, its step supports 16 (a fixed stage budget) and
// fails above; params.fuzz catches it (its round of maxima runs substeps = 64).
#include "substeps_euler.hpp"

struct SupportsFewerSubsteps : clothlab::faulty::SubstepsEulerBase {
  using SubstepsEulerBase::SubstepsEulerBase;
  static constexpr const char* id = "supports-fewer-substeps";
  static constexpr const char* name = "Symplectic Euler supporting 16 of its 64 substeps";
  static constexpr const char* description = "faulty: the schema's range exceeds the step's";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    if (substeps_ > 16)
      throw clothlab::sdk::Error(CLOTHLAB_ERROR_UNSUPPORTED, "at most 16 substeps supported");
    SubstepsEulerBase::step(system, t, dt);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-supports-fewer-substeps", "0.0.1",
                      clothlab::sdk::integrators<SupportsFewerSubsteps>, clothlab::sdk::scenarios<>)
