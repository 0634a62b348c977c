// Spring forces of one stencil along one grid row, each spring computed once.
//
// A spring from particle c of this row to its partner pushes c by f and the partner by
// -f. Stencils that stay in the row store f by column (`own[c] = f`) and are accumulated
// later by a shifted add; stencils reaching a later row add both ends straight into the
// row accumulators (`own[c] += f`, `partner[c] -= f`, partner shifted to line up).
//
// The formula is written once over a lane type: a scalar Real inside an `omp simd` loop,
// or, for float, a block of SIMD lanes per iteration (float_lanes.hpp) with masked ends.
#pragma once

#include <cstddef>
#include <type_traits>

#include "inverse_sqrt.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// Every row below holds its three components `span` elements apart: component k of
// column c at [c + k * span]. One stride for all of them keeps the kernel to six base
// pointers, so they stay in registers.
template <class Real>
struct SpringRow {
  const Real* x;          // positions of this row
  const Real* x_partner;  // positions of the partners, shifted to line up by column
  const Real* v;          // velocities likewise; read only when damped
  const Real* v_partner;
  Real* own;      // by column of the first particle
  Real* partner;  // by column of the first particle; used only when adding forward
  std::size_t span;
  std::size_t col_begin;
  std::size_t col_end;
  Real rest;
  Real ks;
  Real kd;
};

// A spring's law as spring_force_scale reads it: {ks, ks rest / scale, kd / scale^2}, scale
// that of the kernel's inverse square root (inverse_sqrt.hpp), so the kernel never multiplies
// by it.
template <class Lane>
inline void spring_law(Lane rest, Lane ks, Lane kd, float scale, Lane (&law)[3]) {
  const float unit = 1.0f / scale;  // a power of two: exact
  law[0] = ks;
  law[1] = ks * rest * unit;
  law[2] = kd * (unit * unit);
}

// Force on the first particle per unit of d = x_partner - x_own: Hooke (seed eq. 2.7),
// ks (|d| - rest) / |d| = ks - ks rest / |d|, plus damping along the spring (eq. 2.8) when
// Damped, kd (dv . d) / |d|^2 (dv = v_partner - v_own).
template <bool Damped, class Lane>
inline Lane spring_force_scale(Lane dx, Lane dy, Lane dz, Lane dvx, Lane dvy, Lane dvz,
                               const Lane (&law)[3]) {
  const Lane squared = dx * dx + dy * dy + dz * dz;
  const Lane inverse_length = scaled_inverse_sqrt(squared);  // scaled: see spring_law
  if constexpr (Damped) {
    const Lane rate = law[2] * (dvx * dx + dvy * dy + dvz * dz);
    return (rate * inverse_length - law[1]) * inverse_length + law[0];
  }
  return law[0] - law[1] * inverse_length;
}

template <class Real, bool Damped, bool Forward>
inline void spring_row_forces_portable(const SpringRow<Real>& row) {
  const Real* __restrict x = row.x;
  const Real* __restrict xp = row.x_partner;
  const Real* __restrict v = row.v;
  const Real* __restrict vp = row.v_partner;
  Real* __restrict own = row.own;
  Real* __restrict partner = row.partner;
  const std::size_t y = row.span, z = 2 * row.span;
  Real law[3];
  spring_law(row.rest, row.ks, row.kd, kScalarInverseSqrtScale, law);
#pragma omp simd
  for (std::size_t c = row.col_begin; c < row.col_end; ++c) {
    const Real dx = xp[c] - x[c];
    const Real dy = xp[c + y] - x[c + y];
    const Real dz = xp[c + z] - x[c + z];
    Real dvx = 0, dvy = 0, dvz = 0;
    if constexpr (Damped) {
      dvx = vp[c] - v[c];
      dvy = vp[c + y] - v[c + y];
      dvz = vp[c + z] - v[c + z];
    }
    const Real scale = spring_force_scale<Damped>(dx, dy, dz, dvx, dvy, dvz, law);
    if constexpr (Forward) {
      own[c] += scale * dx;
      own[c + y] += scale * dy;
      own[c + z] += scale * dz;
      partner[c] -= scale * dx;
      partner[c + y] -= scale * dy;
      partner[c + z] -= scale * dz;
    } else {
      own[c] = scale * dx;
      own[c + y] = scale * dy;
      own[c + z] = scale * dz;
    }
  }
}

#if defined(CLOTHLAB_FLOAT_LANES)
template <bool Damped, bool Forward>
inline void spring_row_forces_lanes(const SpringRow<float>& row) {
  float row_law[3];
  spring_law(row.rest, row.ks, row.kd, kLanesInverseSqrtScale, row_law);
  const Floats law[3] = {broadcast(row_law[0]), broadcast(row_law[1]), broadcast(row_law[2])};
  const std::size_t span = row.span;
  for_each_lane_block(row.col_begin, row.col_end, [&](std::size_t c, auto lanes) {
    const auto load = [&](const float* p, int k) { return lanes.load(p + c + k * span); };
    const auto store = [&](float* p, int k, Floats value) { lanes.store(p + c + k * span, value); };
    Floats d[3], dv[3] = {};
    for (int k = 0; k < 3; ++k) d[k] = load(row.x_partner, k) - load(row.x, k);
    if constexpr (Damped) {
      for (int k = 0; k < 3; ++k) dv[k] = load(row.v_partner, k) - load(row.v, k);
    }
    const Floats scale = spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], law);
    for (int k = 0; k < 3; ++k) {
      const Floats force = scale * d[k];
      if constexpr (Forward) {
        store(row.own, k, load(row.own, k) + force);
        store(row.partner, k, load(row.partner, k) - force);
      } else {
        store(row.own, k, force);
      }
    }
  });
}
#endif

template <class Real, bool Damped, bool Forward>
inline void spring_row_forces(const SpringRow<Real>& row) {
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    spring_row_forces_lanes<Damped, Forward>(row);
    return;
  }
#endif
  spring_row_forces_portable<Real, Damped, Forward>(row);
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
