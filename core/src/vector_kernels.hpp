// Element-wise vector updates on one span [begin, end) of one component array.
#pragma once

#include <cstddef>
#include <cstdint>

#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
inline void axpy_span(Real* y, Real alpha, const Real* x, std::size_t begin, std::size_t end) {
#pragma omp simd
  for (std::size_t i = begin; i < end; ++i) y[i] += alpha * x[i];
}

// out = base + sum_k coefficients[k] * vectors[k] on [begin, end). out may alias any
// input: each block is summed into a local buffer before any of it is written.
template <class Real>
inline void lincomb_span(Real* out, const Real* base, uint32_t count, const double* coefficients,
                         const void* const* vectors, std::size_t begin, std::size_t end) {
  constexpr std::size_t kBlock = 256;
  for (std::size_t block = begin; block < end; block += kBlock) {
    const std::size_t size = end - block < kBlock ? end - block : kBlock;
    Real sum[kBlock];
#pragma omp simd
    for (std::size_t t = 0; t < size; ++t) sum[t] = base[block + t];
    for (uint32_t k = 0; k < count; ++k) {
      const Real coefficient = static_cast<Real>(coefficients[k]);
      const Real* vector = static_cast<const Real*>(vectors[k]) + block;
#pragma omp simd
      for (std::size_t t = 0; t < size; ++t) sum[t] += coefficient * vector[t];
    }
#pragma omp simd
    for (std::size_t t = 0; t < size; ++t) out[block + t] = sum[t];
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
