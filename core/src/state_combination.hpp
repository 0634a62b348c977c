// A state vector given as a linear combination base + sum_i coefficients[i] * vectors[i]
// (all of 3 * stride elements), and the kernel that forms one grid row of such a sum. The
// force pass forms the rows of a Runge-Kutta stage state as it goes instead of reading a
// stage vector written by an earlier pass.
#pragma once

#include <clothlab/plugin.h>

#include <cstddef>
#include <cstdint>

#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
struct StateCombination {
  static constexpr uint32_t kMaxTerms = CLOTHLAB_COMBINATION_MAX_TERMS;
  const Real* base = nullptr;
  uint32_t count = 0;
  Real coefficients[kMaxTerms] = {};
  const Real* vectors[kMaxTerms] = {};
};

// out[c] = base[c] + sum_t coefficients[t] * vectors[t][c] for active particles, base[c]
// for pinned ones (inverse mass 0), as lincomb leaves them; all pointers at the row.
template <class Real, uint32_t Terms>
inline void combine_row_fused(Real* __restrict out, const Real* __restrict base,
                              const Real* coefficients, const Real* const* vectors,
                              const Real* __restrict inverse_mass, std::size_t cols) {
  const Real* __restrict terms[Terms];
  Real weights[Terms];
  for (uint32_t t = 0; t < Terms; ++t) {
    terms[t] = vectors[t];
    weights[t] = coefficients[t];
  }
  // Terms summed per column in one pass.
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) {
    Real sum = base[c];
    for (uint32_t t = 0; t < Terms; ++t) sum += weights[t] * terms[t][c];
    out[c] = inverse_mass[c] > Real(0) ? sum : base[c];
  }
}

template <class Real>
inline void combine_row(Real* __restrict out, const Real* __restrict base, uint32_t count,
                        const Real* coefficients, const Real* const* vectors,
                        const Real* __restrict inverse_mass, std::size_t cols) {
  switch (count) {
    case 0:
#pragma omp simd
      for (std::size_t c = 0; c < cols; ++c) out[c] = base[c];
      return;
    case 1:
      return combine_row_fused<Real, 1>(out, base, coefficients, vectors, inverse_mass, cols);
    case 2:
      return combine_row_fused<Real, 2>(out, base, coefficients, vectors, inverse_mass, cols);
    case 3:
      return combine_row_fused<Real, 3>(out, base, coefficients, vectors, inverse_mass, cols);
    case 4:
      return combine_row_fused<Real, 4>(out, base, coefficients, vectors, inverse_mass, cols);
    default:
      break;
  }
    // More terms: swept one by one over the row (it stays in L1).
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) out[c] = base[c];
  for (uint32_t t = 0; t < count; ++t) {
    const Real coefficient = coefficients[t];
    const Real* __restrict vector = vectors[t];
#pragma omp simd
    for (std::size_t c = 0; c < cols; ++c) out[c] += coefficient * vector[c];
  }
#pragma omp simd
  for (std::size_t c = 0; c < cols; ++c) out[c] = inverse_mass[c] > Real(0) ? out[c] : base[c];
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
