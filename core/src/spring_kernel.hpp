// Spring forces of one stencil, computed once per spring along a grid row.
//
// The force on a spring's first particle i is stored at f[i]; the second particle
// j = i + offset receives -f[i], which the accumulation pass gathers as -f[j - offset].
// Entries without a spring are never written and stay zero.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace clothlab::detail {

template <class Real>
struct SpringStencilJob {
  const Real* x[3];
  const Real* v[3];  // only read when damped
  Real* f[3];
  std::size_t cols;
  std::size_t col_begin;
  std::size_t col_end;
  std::size_t offset;
  Real rest;
  Real ks;
  Real kd;
};

// Hooke (seed eq. 2.7), plus damping along the spring (eq. 2.8) when Damped.
template <class Real, bool Damped>
inline void spring_row_forces(const SpringStencilJob<Real>& job, std::size_t row) {
  const std::size_t first = row * job.cols;
  const std::size_t offset = job.offset;
  const Real* __restrict x = job.x[0] + first;
  const Real* __restrict y = job.x[1] + first;
  const Real* __restrict z = job.x[2] + first;
  const Real* __restrict vx = job.v[0] + (Damped ? first : 0);
  const Real* __restrict vy = job.v[1] + (Damped ? first : 0);
  const Real* __restrict vz = job.v[2] + (Damped ? first : 0);
  Real* __restrict fx = job.f[0] + first;
  Real* __restrict fy = job.f[1] + first;
  Real* __restrict fz = job.f[2] + first;
  const Real rest = job.rest;
  const Real ks = job.ks;
  const Real kd = job.kd;
#pragma omp simd
  for (std::size_t c = job.col_begin; c < job.col_end; ++c) {
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
