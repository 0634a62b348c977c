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

}  // namespace clothlab::faulty
