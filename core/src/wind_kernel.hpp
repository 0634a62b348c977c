// Wind pressure on the two triangles of each grid cell along one row of cells
// (seed eq. 3.2, per triangle).
//
// Cell c has corners a = c, b = c + 1 in this row and c' = c, d = c + 1 in the next;
// triangles (a, b, c') and (b, d, c'). Each gets F = strength * area * (n_hat . w) n_hat,
// a third to each corner; the per-corner share is stored at the cell's column in `first`
// (triangle abc') and `second` (triangle bdc'), gathered later by shifted reads.
#pragma once

#include <cmath>
#include <cstddef>

namespace clothlab::detail {

template <class Real>
struct WindRow {
  const Real* x[3];      // positions, at this row's first particle
  const Real* below[3];  // positions, at the next row's first particle
  Real* first[3];
  Real* second[3];
  std::size_t cells;  // cols - 1
  Real direction[3];
  Real strength;
};

template <class Real>
inline void triangle_wind_share(Real e1x, Real e1y, Real e1z, Real e2x, Real e2y, Real e2z,
                                const Real (&w)[3], Real strength_sixth, Real& fx, Real& fy,
                                Real& fz) {
  const Real nx = e1y * e2z - e1z * e2y;
  const Real ny = e1z * e2x - e1x * e2z;
  const Real nz = e1x * e2y - e1y * e2x;
  const Real norm = std::sqrt(nx * nx + ny * ny + nz * nz);
  // area * (n_hat . w) n_hat / 3 = (n . w) n / (6 |n|); a degenerate triangle gets none.
  const Real inverse = norm > Real(0) ? Real(1) / norm : Real(0);
  const Real scale = strength_sixth * (nx * w[0] + ny * w[1] + nz * w[2]) * inverse;
  fx = scale * nx;
  fy = scale * ny;
  fz = scale * nz;
}

template <class Real>
inline void wind_row_forces(const WindRow<Real>& row) {
  const Real* __restrict x = row.x[0];
  const Real* __restrict y = row.x[1];
  const Real* __restrict z = row.x[2];
  const Real* __restrict xb = row.below[0];
  const Real* __restrict yb = row.below[1];
  const Real* __restrict zb = row.below[2];
  Real* __restrict ax = row.first[0];
  Real* __restrict ay = row.first[1];
  Real* __restrict az = row.first[2];
  Real* __restrict bx = row.second[0];
  Real* __restrict by = row.second[1];
  Real* __restrict bz = row.second[2];
  const Real w[3] = {row.direction[0], row.direction[1], row.direction[2]};
  const Real strength_sixth = row.strength / Real(6);
#pragma omp simd
  for (std::size_t c = 0; c < row.cells; ++c) {
    triangle_wind_share(x[c + 1] - x[c], y[c + 1] - y[c], z[c + 1] - z[c], xb[c] - x[c],
                        yb[c] - y[c], zb[c] - z[c], w, strength_sixth, ax[c], ay[c], az[c]);
    triangle_wind_share(xb[c + 1] - x[c + 1], yb[c + 1] - y[c + 1], zb[c + 1] - z[c + 1],
                        xb[c] - x[c + 1], yb[c] - y[c + 1], zb[c] - z[c + 1], w, strength_sixth,
                        bx[c], by[c], bz[c]);
  }
}

}  // namespace clothlab::detail
