// Wind pressure on the two triangles of each grid cell (seed eq. 3.2, per triangle).
//
// Cell (r, c) has corners a = i, b = i + 1, c = i + cols, d = i + cols + 1 and triangles
// (a, b, c) and (b, d, c). Each triangle gets F = strength * area * (n_hat . w) n_hat,
// a third to each corner; the per-corner share is stored at the cell's index i in
// `first` (triangle abc) and `second` (triangle bdc), gathered later by shifted adds.
#pragma once

#include <cmath>
#include <cstddef>

namespace clothlab::detail {

template <class Real>
struct WindJob {
  const Real* x[3];
  Real* first[3];
  Real* second[3];
  std::size_t cols;
  Real direction[3];
  Real strength;
};

template <class Real>
inline void triangle_wind_share(Real e1x, Real e1y, Real e1z, Real e2x, Real e2y, Real e2z,
                                const Real (&w)[3], Real strength, Real& fx, Real& fy, Real& fz) {
  const Real nx = e1y * e2z - e1z * e2y;
  const Real ny = e1z * e2x - e1x * e2z;
  const Real nz = e1x * e2y - e1y * e2x;
  const Real norm = std::sqrt(nx * nx + ny * ny + nz * nz);
  // area * (n_hat . w) n_hat / 3 = (n . w) n / (6 |n|); a degenerate triangle gets none.
  const Real inverse = norm > Real(0) ? Real(1) / norm : Real(0);
  const Real scale = strength * (nx * w[0] + ny * w[1] + nz * w[2]) * inverse / Real(6);
  fx = scale * nx;
  fy = scale * ny;
  fz = scale * nz;
}

template <class Real>
inline void wind_row_forces(const WindJob<Real>& job, std::size_t row) {
  const std::size_t first_index = row * job.cols;
  const std::size_t cols = job.cols;
  const Real* __restrict x = job.x[0] + first_index;
  const Real* __restrict y = job.x[1] + first_index;
  const Real* __restrict z = job.x[2] + first_index;
  Real* __restrict ax = job.first[0] + first_index;
  Real* __restrict ay = job.first[1] + first_index;
  Real* __restrict az = job.first[2] + first_index;
  Real* __restrict bx = job.second[0] + first_index;
  Real* __restrict by = job.second[1] + first_index;
  Real* __restrict bz = job.second[2] + first_index;
  const Real w[3] = {job.direction[0], job.direction[1], job.direction[2]};
  const Real strength = job.strength;
  const std::size_t cells = cols - 1;
#pragma omp simd
  for (std::size_t c = 0; c < cells; ++c) {
    const std::size_t b = c + 1, d = c + cols, e = c + cols + 1;  // corners after a = c
    triangle_wind_share(x[b] - x[c], y[b] - y[c], z[b] - z[c], x[d] - x[c], y[d] - y[c],
                        z[d] - z[c], w, strength, ax[c], ay[c], az[c]);
    triangle_wind_share(x[e] - x[b], y[e] - y[b], z[e] - z[b], x[d] - x[b], y[d] - y[b],
                        z[d] - z[b], w, strength, bx[c], by[c], bz[c]);
  }
}

}  // namespace clothlab::detail
