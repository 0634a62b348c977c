// The projection of particles onto their tethers (xpbd_tethers.hpp), compiled per SIMD target
// with the grid sweep that calls it row by row (xpbd_grid_sweep.hpp); the general sweep calls
// its own build's copy.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "simd_namespace.hpp"
#include "xpbd_tethers.hpp"

namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE {

// Projects particles [begin, end) onto their tethers, slot by slot: dx is the substep's
// displacement (the particle is at x + dx), pins (inverse mass 0) are left alone.
// In double whatever Real is: a tether is up to the cloth's size long, float32 resolves
// d = x + dx - anchor ~ 1 m only to ~6e-8 m, and that rounding, new every substep, would
// enter the correction, which v = dx / h turns into ~1e-3 m/s (the conformance runner's
// float32-against-float64 check sees it; a spring, a few mm long, needs no such care).
template <class Real>
inline void project_tethers(const Tethers<Real>& tethers, std::size_t begin, std::size_t end,
                            const Real* __restrict x, Real* __restrict dx,
                            const Real* __restrict inverse_mass, std::size_t stride) {
  const std::size_t count = tethers.anchor_count();
  const double* ax = tethers.anchor_positions();
  const double *ay = ax + count, *az = ay + count;
  const Real *x0 = x, *x1 = x + stride, *x2 = x + 2 * stride;
  Real *dx0 = dx, *dx1 = dx + stride, *dx2 = dx + 2 * stride;
  for (uint32_t slot = 0; slot < tethers.slots(); ++slot) {
    const uint32_t* anchor = tethers.slot_anchors(slot);
    const Real* limit = tethers.slot_limits(slot);
#pragma omp simd
    for (std::size_t i = begin; i < end; ++i) {
      const uint32_t a = anchor[i];
      const double d0 = (double{x0[i]} - ax[a]) + double{dx0[i]};
      const double d1 = (double{x1[i]} - ay[a]) + double{dx1[i]};
      const double d2 = (double{x2[i]} - az[a]) + double{dx2[i]};
      const double squared = d0 * d0 + d1 * d1 + d2 * d2;
      const double most = limit[i];
      // Past its limit the particle moves onto the sphere: d -> d limit / |d|. Inside, and
      // on a pin (whose limit is infinite), nothing moves: the tether is unilateral. (Both
      // tests in double and without a short circuit, or the loop does not vectorise.)
      const bool taut = (double{inverse_mass[i]} != 0) & (squared > most * most);
      const double shrink = taut ? most / std::sqrt(squared) - 1 : 0.0;
      dx0[i] += static_cast<Real>(shrink * d0);
      dx1[i] += static_cast<Real>(shrink * d1);
      dx2[i] += static_cast<Real>(shrink * d2);
    }
  }
}

}  // namespace clothlab::builtin::inline CLOTHLAB_SIMD_NAMESPACE
