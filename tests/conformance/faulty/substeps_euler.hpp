// Symplectic Euler in `substeps` equal substeps: the honest core of the faulty plugins that
// get their parameters wrong (params.*). Each changes one thing about it.
#pragma once

#include "symplectic_euler.hpp"

namespace clothlab::faulty {

struct SubstepsEulerBase : SymplecticEulerBase {
  static constexpr std::array<clothlab_param_spec, 1> params{
      sdk::int_param("substeps", 1, 1, 64, "equal substeps per step")};

  explicit SubstepsEulerBase(const sdk::Params& values)
      : SymplecticEulerBase(values), substeps_(values.integer("substeps")) {}

  template <class Real>
  void step(sdk::System<Real>& system, double t, double dt) {
    const double h = dt / static_cast<double>(substeps_);
    for (long i = 0; i < substeps_; ++i) SymplecticEulerBase::step(system, t + i * h, h);
  }

  long substeps_;
};

// A library of one integrator whose descriptor is the SDK's with `edit` applied (a fault the
// SDK itself would not let through).
template <class Impl, class Edit>
const clothlab_plugin_descriptor* edited_library(const char* library_name, Edit edit) {
  static const clothlab_integrator integrator = [&] {
    clothlab_integrator copy = *sdk::integrators<Impl>::list()[0];
    edit(copy);
    return copy;
  }();
  static const clothlab_integrator* const integrators[] = {&integrator};
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR},
      sizeof(clothlab_plugin_descriptor),
      1,
      0,
      0,
      library_name,
      "0.0.1",
      integrators,
      nullptr,
  };
  return &descriptor;
}

}  // namespace clothlab::faulty
