// Wind pressure on the two triangles of each grid cell along one row of cells
// (seed eq. 3.2, per triangle).
//
// The cell's two triangles (grid_cell.hpp) each get F = strength * area * (n_hat . w) n_hat,
// a third to each corner; the per-corner share is stored at the cell's column in `first`
// (triangle abc') and `second` (triangle bdc'), gathered later by shifted reads.
//
// Written once over a lane type like the spring kernel: scalar in an `omp simd` loop, or a
// block of SIMD lanes per iteration for float.
#pragma once

#include <cstddef>
#include <type_traits>

#include "grid_cell.hpp"
#include "inverse_sqrt.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// Rows hold their components a span apart, as in the spring kernel: the positions
// position_span apart (a scratch row's span, or the state's stride when read in place),
// the shares span apart.
template <class Real>
struct WindRow {
  const Real* x;      // positions of this row
  const Real* below;  // positions of the next row
  Real* first;
  Real* second;
  std::size_t position_span;
  std::size_t span;
  std::size_t cells;  // cols - 1
  Real direction[3];
  Real strength;
};

// The wind as triangle_wind_share reads it: direction times strength / 6, over the scale of the
// kernel's inverse square root (inverse_sqrt.hpp), so the kernel never multiplies by either.
template <class Real>
inline void wind_pressure(const Real (&direction)[3], Real strength, float scale,
                          Real (&pressure)[3]) {
  const Real factor = strength / (Real(6) * Real(scale));
  for (int k = 0; k < 3; ++k) pressure[k] = direction[k] * factor;
}

// Per-corner share of the wind force on the triangle with edges e1, e2 from one corner.
template <class Lane>
inline void triangle_wind_share(const Lane (&e1)[3], const Lane (&e2)[3], const Lane (&pressure)[3],
                                Lane (&share)[3]) {
  const Lane n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                     e1[0] * e2[1] - e1[1] * e2[0]};
  // area * (n_hat . w) n_hat / 3 = (n . w) n / (6 |n|); a degenerate triangle gets none.
  const Lane inverse_norm = scaled_inverse_sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const Lane scale = (n[0] * pressure[0] + n[1] * pressure[1] + n[2] * pressure[2]) * inverse_norm;
  for (int k = 0; k < 3; ++k) share[k] = scale * n[k];
}

// The shares of both triangles of a cell from its corners a, b (this row), c', d (next).
template <class Lane>
inline void cell_wind_shares(const Lane (&a)[3], const Lane (&b)[3], const Lane (&c)[3],
                             const Lane (&d)[3], const Lane (&pressure)[3], Lane (&first)[3],
                             Lane (&second)[3]) {
  Lane ab[3], ac[3], bd[3], bc[3];
  cell_triangle_edges(a, b, c, d, ab, ac, bd, bc);
  triangle_wind_share(ab, ac, pressure, first);
  triangle_wind_share(bd, bc, pressure, second);
}

template <class Real>
inline void wind_row_forces_portable(const WindRow<Real>& row) {
  const Real* __restrict x = row.x;
  const Real* __restrict below = row.below;
  Real* __restrict first = row.first;
  Real* __restrict second = row.second;
  const std::size_t y = row.span, z = 2 * row.span;
  Real pressure[3];
  wind_pressure(row.direction, row.strength, kScalarInverseSqrtScale, pressure);
#pragma omp simd
  for (std::size_t c = 0; c < row.cells; ++c) {
    Real a[3], b[3], c_[3], d[3];
    load_cell_corners(x, below, c, row.position_span, a, b, c_, d);
    Real share_first[3], share_second[3];
    cell_wind_shares(a, b, c_, d, pressure, share_first, share_second);
    first[c] = share_first[0];
    first[c + y] = share_first[1];
    first[c + z] = share_first[2];
    second[c] = share_second[0];
    second[c + y] = share_second[1];
    second[c + z] = share_second[2];
  }
}

#if defined(CLOTHLAB_FLOAT_LANES)
inline void wind_row_forces_lanes(const WindRow<float>& row) {
  float row_pressure[3];
  wind_pressure(row.direction, row.strength, kLanesInverseSqrtScale, row_pressure);
  const Floats pressure[3] = {broadcast(row_pressure[0]), broadcast(row_pressure[1]),
                              broadcast(row_pressure[2])};
  const std::size_t span = row.span, position_span = row.position_span;
  // The pointers in locals: stores through row.first could alias row itself, so read through
  // it, every pointer would be loaded again each block.
  const float* const x = row.x;
  const float* const next = row.below;
  float* const first_out = row.first;
  float* const second_out = row.second;
  // The shares alias no position.
  for_each_whole_lane_block(0, row.cells, [&](std::size_t c, auto lanes) {
    const auto load = [&](const float* p, std::size_t k) {
      return lanes.load(p + c + k * position_span);
    };
    Floats a[3], b[3], below[3], d[3], first[3], second[3];
    for (std::size_t k = 0; k < 3; ++k) {
      a[k] = load(x, k);
      b[k] = load(x + 1, k);
      below[k] = load(next, k);
      d[k] = load(next + 1, k);
    }
    cell_wind_shares(a, b, below, d, pressure, first, second);
    for (std::size_t k = 0; k < 3; ++k) {
      lanes.store(first_out + c + k * span, first[k]);
      lanes.store(second_out + c + k * span, second[k]);
    }
  });
}
#endif

template <class Real>
inline void wind_row_forces(const WindRow<Real>& row) {
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    wind_row_forces_lanes(row);
    return;
  }
#endif
  wind_row_forces_portable(row);
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
