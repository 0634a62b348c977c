// Shifted adds that move per-spring and per-triangle forces stored by column onto the
// particles of a row accumulator (see force_pipeline.hpp). Inputs are zero outside the
// columns that hold a spring or cell, including a margin left of column 0.
#pragma once

#include <cstddef>

#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// A spring from column c to column c + step of the same row: acc[c] += f[c] - f[c - step].
template <class Real>
inline void add_row_springs(Real* __restrict acc, const Real* __restrict f, std::size_t step,
                            std::size_t cols) {
  const Real* __restrict f_back = f - step;
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) acc[c] += f[c] - f_back[c];
}

// Wind shares of the cells starting in this row (first: triangle abc', second: bdc'): a
// particle of this row is corner a of its own cell and b of the cell to its left; one of
// the next row is corner c' of the cell above it and d of the cell above-left.
template <class Real>
inline void add_cell_winds(Real* __restrict acc, Real* __restrict acc_next,
                           const Real* __restrict first, const Real* __restrict second,
                           std::size_t cols) {
  const Real* __restrict first_left = first - 1;
  const Real* __restrict second_left = second - 1;
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) {
    acc[c] += first[c] + first_left[c] + second_left[c];
    acc_next[c] += first[c] + second[c] + second_left[c];
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
