// Spring forces of one stencil along one grid row, each spring computed once.
//
// A spring from particle c of this row to its partner pushes c by f and the partner by
// -f. Stencils that stay in the row store f by column (`own[c] = f`) and are accumulated
// later by a shifted add; stencils reaching a later row add both ends straight into the
// row accumulators (`own[c] += f`, `partner[c] -= f`, partner shifted to line up).
//
// The formula is written once over a lane type: a scalar Real inside an `omp simd` loop,
// or, for float on AVX-512, 16 lanes per iteration with masked ends.
#pragma once

#include <cstddef>
#include <type_traits>

#include "inverse_sqrt.hpp"

namespace clothlab::detail {

template <class Real>
struct SpringRow {
  const Real* x[3];          // positions of this row, by column
  const Real* x_partner[3];  // positions of the partners, shifted to line up by column
  const Real* v[3];          // velocities likewise; read only when damped
  const Real* v_partner[3];
  Real* own[3];      // by column of the first particle
  Real* partner[3];  // by column of the first particle; used only when adding forward
  std::size_t col_begin;
  std::size_t col_end;
  Real rest;
  Real ks;
  Real kd;
};

// Force on the first particle per unit of d = x_partner - x_own: Hooke (seed eq. 2.7),
// plus damping along the spring (eq. 2.8) when Damped (dv = v_partner - v_own).
template <bool Damped, class Lane>
inline Lane spring_force_scale(Lane dx, Lane dy, Lane dz, Lane dvx, Lane dvy, Lane dvz, Lane rest,
                               Lane ks, Lane kd) {
  const Lane squared = dx * dx + dy * dy + dz * dz;
  const Lane inverse_length = inverse_sqrt_or_zero(squared);
  Lane magnitude = ks * (squared * inverse_length - rest);
  if constexpr (Damped) magnitude += kd * (dvx * dx + dvy * dy + dvz * dz) * inverse_length;
  return magnitude * inverse_length;
}

template <class Real, bool Damped, bool Forward>
inline void spring_row_forces_portable(const SpringRow<Real>& row) {
  const Real* __restrict x = row.x[0];
  const Real* __restrict y = row.x[1];
  const Real* __restrict z = row.x[2];
  const Real* __restrict xp = row.x_partner[0];
  const Real* __restrict yp = row.x_partner[1];
  const Real* __restrict zp = row.x_partner[2];
  const Real* __restrict vx = row.v[0];
  const Real* __restrict vy = row.v[1];
  const Real* __restrict vz = row.v[2];
  const Real* __restrict vxp = row.v_partner[0];
  const Real* __restrict vyp = row.v_partner[1];
  const Real* __restrict vzp = row.v_partner[2];
  Real* __restrict fx = row.own[0];
  Real* __restrict fy = row.own[1];
  Real* __restrict fz = row.own[2];
  Real* __restrict px = row.partner[0];
  Real* __restrict py = row.partner[1];
  Real* __restrict pz = row.partner[2];
  const Real rest = row.rest;
  const Real ks = row.ks;
  const Real kd = row.kd;
#pragma omp simd
  for (std::size_t c = row.col_begin; c < row.col_end; ++c) {
    const Real dx = xp[c] - x[c];
    const Real dy = yp[c] - y[c];
    const Real dz = zp[c] - z[c];
    Real dvx = 0, dvy = 0, dvz = 0;
    if constexpr (Damped) {
      dvx = vxp[c] - vx[c];
      dvy = vyp[c] - vy[c];
      dvz = vzp[c] - vz[c];
    }
    const Real scale = spring_force_scale<Damped>(dx, dy, dz, dvx, dvy, dvz, rest, ks, kd);
    if constexpr (Forward) {
      fx[c] += scale * dx;
      fy[c] += scale * dy;
      fz[c] += scale * dz;
      px[c] -= scale * dx;
      py[c] -= scale * dy;
      pz[c] -= scale * dz;
    } else {
      fx[c] = scale * dx;
      fy[c] = scale * dy;
      fz[c] = scale * dz;
    }
  }
}

#if defined(__AVX512F__)
template <bool Damped, bool Forward>
inline void spring_row_forces_avx512(const SpringRow<float>& row) {
  const __m512 rest = _mm512_set1_ps(row.rest);
  const __m512 ks = _mm512_set1_ps(row.ks);
  const __m512 kd = _mm512_set1_ps(row.kd);
  for (std::size_t c = row.col_begin; c < row.col_end; c += 16) {
    const std::size_t left = row.col_end - c;
    const __mmask16 lanes = left >= 16 ? __mmask16(0xFFFF) : __mmask16((1u << left) - 1);
    const auto load = [&](const float* p) { return _mm512_maskz_loadu_ps(lanes, p + c); };
    const auto store = [&](float* p, __m512 value) { _mm512_mask_storeu_ps(p + c, lanes, value); };
    __m512 d[3], dv[3] = {};
    for (int k = 0; k < 3; ++k) d[k] = load(row.x_partner[k]) - load(row.x[k]);
    if constexpr (Damped) {
      for (int k = 0; k < 3; ++k) dv[k] = load(row.v_partner[k]) - load(row.v[k]);
    }
    const __m512 scale =
        spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], rest, ks, kd);
    for (int k = 0; k < 3; ++k) {
      const __m512 force = scale * d[k];
      if constexpr (Forward) {
        store(row.own[k], load(row.own[k]) + force);
        store(row.partner[k], load(row.partner[k]) - force);
      } else {
        store(row.own[k], force);
      }
    }
  }
}
#endif

template <class Real, bool Damped, bool Forward>
inline void spring_row_forces(const SpringRow<Real>& row) {
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<Real, float>) {
    spring_row_forces_avx512<Damped, Forward>(row);
    return;
  }
#endif
  spring_row_forces_portable<Real, Damped, Forward>(row);
}

}  // namespace clothlab::detail
