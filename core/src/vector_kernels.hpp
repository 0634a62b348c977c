// Element-wise vector updates on one span [begin, end) of one component array.
#pragma once

#include <cstddef>
#include <cstdint>

namespace clothlab::detail {

template <class Real>
inline void axpy_span(Real* y, Real alpha, const Real* x, std::size_t begin, std::size_t end) {
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) y[i] += alpha * x[i];
}

// out = base + sum_k coefficients[k] * vectors[k]; out may alias any input, since each
// element is read completely before it is written.
template <class Real>
inline void lincomb_span(Real* out, const Real* base, uint32_t count, const double* coefficients,
                         const void* const* vectors, std::size_t begin, std::size_t end) {
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) {
    Real sum = base[i];
    for (uint32_t k = 0; k < count; ++k) {
      sum += static_cast<Real>(coefficients[k]) * static_cast<const Real*>(vectors[k])[i];
    }
    out[i] = sum;
  }
}

}  // namespace clothlab::detail
