// Spring forces of one stencil along one grid row, each spring computed once.
//
// A spring from particle c of this row to its partner pushes c by f and the partner by
// -f. Stencils that stay in the row store f by column (`own[c] = f`) and are accumulated
// later by a shifted add; stencils reaching a later row add both ends straight into the
// row accumulators (`own[c] += f`, `partner[c] -= f`, partner shifted to line up).
#pragma once

#include <cmath>
#include <cstddef>

namespace clothlab::detail {

template <class Real>
struct SpringRow {
  const Real* x[3];  // positions, at this row's first particle
  const Real* v[3];  // velocities likewise; read only when damped
  Real* own[3];      // by column of the first particle
  Real* partner[3];  // by column of the first particle; used only when adding forward
  std::size_t col_begin;
  std::size_t col_end;
  std::size_t offset;  // index distance to the second particle
  Real rest;
  Real ks;
  Real kd;
};

// Hooke (seed eq. 2.7), plus damping along the spring (eq. 2.8) when Damped.
template <class Real, bool Damped, bool Forward>
inline void spring_row_forces(const SpringRow<Real>& row) {
  const std::size_t offset = row.offset;
  const Real* __restrict x = row.x[0];
  const Real* __restrict y = row.x[1];
  const Real* __restrict z = row.x[2];
  const Real* __restrict vx = row.v[0];
  const Real* __restrict vy = row.v[1];
  const Real* __restrict vz = row.v[2];
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
    const Real dx = x[c + offset] - x[c];
    const Real dy = y[c + offset] - y[c];
    const Real dz = z[c + offset] - z[c];
    const Real length = std::sqrt(dx * dx + dy * dy + dz * dz);
    // Coincident particles have no direction: the spring then exerts no force.
    const Real inverse_length = length > Real(0) ? Real(1) / length : Real(0);
    Real magnitude = ks * (length - rest);
    if constexpr (Damped) {
      const Real closing = (vx[c + offset] - vx[c]) * dx + (vy[c + offset] - vy[c]) * dy +
                           (vz[c + offset] - vz[c]) * dz;
      magnitude += kd * closing * inverse_length;
    }
    const Real scale = magnitude * inverse_length;
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

}  // namespace clothlab::detail
