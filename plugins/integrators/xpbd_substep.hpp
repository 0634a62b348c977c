// The arrays and step lengths of one XPBD substep, as both sweeps (xpbd_general_sweep.hpp,
// xpbd_grid_sweep.hpp) read them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "xpbd_tethers.hpp"

namespace clothlab::builtin {

template <class Real>
struct Substep {
  const Real* inverse_mass;
  const Real* external_acceleration;
  // x's change in this substep, exact where x's rounding is not; the grid path keeps it
  // in v and this holds its pins' velocities
  Real* displacement;
  Real* x;
  Real* v;
  const Tethers<Real>* tethers;  // nullptr: off
  uint32_t particle_count;
  std::size_t stride;
  Real h, h_squared, inverse_h;
};

}  // namespace clothlab::builtin
