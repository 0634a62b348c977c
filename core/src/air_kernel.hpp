// The drag and lift of clothlab.air/1 (clothlab/ext/air.h) on the two triangles of each grid
// cell along one row of cells (grid_cell.hpp), added to the per-corner shares the wind kernel
// writes (wind_kernel.hpp: `first` and `second` at the cell's column).
//
// With N = e1 x e2 (|N| = 2 area) and the relative air velocity u = wind - mean corner velocity,
// the header's forces are, without any normalised vector,
//   D = density C_d |u . N| u / 4,   L = density C_l (u . N) (|u|^2 N - (u . N) u) / (4 |N| |u|),
// a third of each to every corner. A degenerate triangle or a still stream gets no lift (and,
// as the products say, no drag). Scalar in an `omp simd` loop: air scenes are not the hot path
// the wind's SIMD kernel is written for.
#pragma once

#include <cmath>
#include <cstddef>

#include "grid_cell.hpp"
#include "inverse_sqrt.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
struct AirRow {
  const Real* x;        // positions of this row
  const Real* below;    // positions of the next row
  const Real* v;        // velocities of this row; nullptr: the cloth counts as at rest
  const Real* v_below;  // velocities of the next row
  Real* first;          // shares, added to
  Real* second;
  std::size_t position_span;  // between the position (and velocity) rows' components
  std::size_t span;           // between the shares' components
  std::size_t cells;          // cols - 1
  Real wind[3];               // m/s
  Real drag_twelfth;          // density C_d / 12: a quarter, shared by three corners
  Real lift_twelfth;          // density C_l / 12
};

// Per-corner share of the air force on the triangle with edges e1, e2 from one corner, the
// triangle moving at `velocity`.
template <class Real>
inline void triangle_air_share(const Real (&e1)[3], const Real (&e2)[3], const Real (&velocity)[3],
                               const Real (&wind)[3], Real drag_twelfth, Real lift_twelfth,
                               Real (&share)[3]) {
  const Real n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
  Real u[3];
  for (int k = 0; k < 3; ++k) u[k] = wind[k] - velocity[k];
  const Real u_n = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
  const Real u_u = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
  const Real n_n = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  const Real drag = drag_twelfth * std::abs(u_n);
  const Real lift = lift_twelfth * u_n * inverse_sqrt_or_zero(n_n * u_u);
  for (int k = 0; k < 3; ++k) share[k] = drag * u[k] + lift * (u_u * n[k] - u_n * u[k]);
}

template <class Real>
inline void add_air_row_forces(const AirRow<Real>& row) {
  const Real* __restrict x = row.x;
  const Real* __restrict below = row.below;
  const Real* __restrict v = row.v;
  const Real* __restrict v_below = row.v_below;
  Real* __restrict first = row.first;
  Real* __restrict second = row.second;
  const std::size_t y = row.span, z = 2 * row.span;
  const Real wind[3] = {row.wind[0], row.wind[1], row.wind[2]};
  const Real third = Real(1) / Real(3);
#pragma omp simd
  for (std::size_t c = 0; c < row.cells; ++c) {
    Real a[3], b[3], c_[3], d[3], ab[3], ac[3], bd[3], bc[3];
    load_cell_corners(x, below, c, row.position_span, a, b, c_, d);
    cell_triangle_edges(a, b, c_, d, ab, ac, bd, bc);
    Real v_first[3] = {0, 0, 0}, v_second[3] = {0, 0, 0};
    if (v != nullptr) {
      for (int k = 0; k < 3; ++k) {
        const std::size_t s = k * row.position_span;
        v_first[k] = (v[c + s] + v[c + 1 + s] + v_below[c + s]) * third;
        v_second[k] = (v[c + 1 + s] + v_below[c + 1 + s] + v_below[c + s]) * third;
      }
    }
    Real share_first[3], share_second[3];
    triangle_air_share(ab, ac, v_first, wind, row.drag_twelfth, row.lift_twelfth, share_first);
    triangle_air_share(bd, bc, v_second, wind, row.drag_twelfth, row.lift_twelfth, share_second);
    first[c] += share_first[0];
    first[c + y] += share_first[1];
    first[c + z] += share_first[2];
    second[c] += share_second[0];
    second[c + y] += share_second[1];
    second[c + z] += share_second[2];
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
