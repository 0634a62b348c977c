// A state vector given as a linear combination base + sum_i coefficients[i] * vectors[i]
// (all of 3 * stride elements), and the kernel that forms one grid row of it. The force
// pass forms the rows of a Runge-Kutta stage state as it goes instead of reading a stage
// vector written by an earlier pass.
#pragma once

#include <clothlab/plugin.h>

#include <cstddef>
#include <cstdint>

namespace clothlab::detail {

template <class Real>
struct StateCombination {
  static constexpr uint32_t kMaxTerms = CLOTHLAB_COMBINATION_MAX_TERMS;
  const Real* base = nullptr;
  uint32_t count = 0;
  Real coefficients[kMaxTerms] = {};
  const Real* vectors[kMaxTerms] = {};
};

// out[c] = the combination at element first + c for active particles, the base value for
// pinned ones (inverse mass 0), as lincomb leaves them.
// Terms summed per column in one pass, for a fixed number of terms.
template <class Real, uint32_t Terms>
inline void combine_row_fused(Real* __restrict out, const StateCombination<Real>& state,
                              std::size_t first, const Real* __restrict inverse_mass,
                              std::size_t cols) {
  const Real* __restrict base = state.base + first;
  const Real* __restrict vectors[Terms > 0 ? Terms : 1];
  Real coefficients[Terms > 0 ? Terms : 1];
  for (uint32_t term = 0; term < Terms; ++term) {
    vectors[term] = state.vectors[term] + first;
    coefficients[term] = state.coefficients[term];
  }
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) {
    Real sum = base[c];
    for (uint32_t term = 0; term < Terms; ++term) sum += coefficients[term] * vectors[term][c];
    out[c] = inverse_mass[c] > Real(0) ? sum : base[c];
  }
}

template <class Real>
inline void combine_row(Real* __restrict out, const StateCombination<Real>& state,
                        std::size_t first, const Real* __restrict inverse_mass, std::size_t cols) {
  switch (state.count) {
    case 0: {
      const Real* __restrict base = state.base + first;
#pragma omp simd
      for (std::size_t c = 0; c < cols; ++c) out[c] = base[c];
      return;
    }
    case 1:
      return combine_row_fused<Real, 1>(out, state, first, inverse_mass, cols);
    case 2:
      return combine_row_fused<Real, 2>(out, state, first, inverse_mass, cols);
    case 3:
      return combine_row_fused<Real, 3>(out, state, first, inverse_mass, cols);
    default:
      break;
  }
  // More terms: swept one by one over the row (stays in L1).
  const Real* __restrict base = state.base + first;
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) out[c] = base[c];
  for (uint32_t term = 0; term < state.count; ++term) {
    const Real coefficient = state.coefficients[term];
    const Real* __restrict vector = state.vectors[term] + first;
#pragma omp simd
    for (std::size_t c = 0; c < cols; ++c) out[c] += coefficient * vector[c];
  }
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) out[c] = inverse_mass[c] > Real(0) ? out[c] : base[c];
}

}  // namespace clothlab::detail
