// Spring forces of one stencil along one grid row, each spring computed once.
//
// The force on a spring's first particle (column c of this row) is stored at f[c]; its
// second particle receives -f[c], which the accumulation pass gathers by a shifted read.
#pragma once

#include <cmath>
#include <cstddef>

namespace clothlab::detail {

template <class Real>
struct SpringRow {
  const Real* x[3];  // positions, at this row's first particle
  const Real* v[3];  // velocities likewise; read only when damped
  Real* f[3];        // per-spring force on the first particle, by column
  std::size_t col_begin;
  std::size_t col_end;
  std::size_t offset;  // index distance to the second particle
  Real rest;
  Real ks;
  Real kd;
};

// Hooke (seed eq. 2.7), plus damping along the spring (eq. 2.8) when Damped.
template <class Real, bool Damped>
inline void spring_row_forces(const SpringRow<Real>& row) {
  const std::size_t offset = row.offset;
  const Real* __restrict x = row.x[0];
  const Real* __restrict y = row.x[1];
  const Real* __restrict z = row.x[2];
  const Real* __restrict vx = row.v[0];
  const Real* __restrict vy = row.v[1];
  const Real* __restrict vz = row.v[2];
  Real* __restrict fx = row.f[0];
  Real* __restrict fy = row.f[1];
  Real* __restrict fz = row.f[2];
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
    fx[c] = scale * dx;
    fy[c] = scale * dy;
    fz[c] = scale * dz;
  }
}

}  // namespace clothlab::detail
