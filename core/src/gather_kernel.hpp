// Gathering per-spring and per-triangle forces onto the particles of one grid row by
// shifted reads of the ring rows (see force_pipeline.hpp).
#pragma once

#include <array>
#include <cstddef>

namespace clothlab::detail {

// out[c] (= or +=) sum over m of own[m][c] - back[m][c]: a spring stored at its first
// particle pushes that particle by f and its second particle by -f. Several stencils
// per pass keep the read-modify-write of `out` to one per pass.
template <class Real, std::size_t M, bool Assign>
inline void gather_springs(Real* __restrict out, const std::array<const Real*, M>& own,
                           const std::array<const Real*, M>& back, std::size_t cols) {
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) {
    Real sum = Assign ? Real(0) : out[c];
    for (std::size_t m = 0; m < M; ++m) sum += own[m][c] - back[m][c];
    out[c] = sum;
  }
}

// Wind shares: a particle is corner a of its own cell, b of the cell to its left, c of
// the cell above and d of the cell above-left (first: triangle abc, second: bdc).
template <class Real, bool Assign>
inline void gather_wind(Real* __restrict out, const Real* __restrict first,
                        const Real* __restrict second, const Real* __restrict first_above,
                        const Real* __restrict second_above, std::size_t cols) {
  const Real* __restrict first_left = first - 1;
  const Real* __restrict second_left = second - 1;
  const Real* __restrict second_above_left = second_above - 1;
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) {
    const Real sum = first[c] + first_left[c] + second_left[c] + first_above[c] + second_above[c] +
                     second_above_left[c];
    out[c] = Assign ? sum : out[c] + sum;
  }
}

}  // namespace clothlab::detail
