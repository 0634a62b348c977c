// The finish stage of ForcePipeline (force_pipeline.hpp): a row whose forces are complete
// becomes accelerations (gravity added, 0 where pinned), and its accumulators are readied for
// the row three below that reuses them.
#include <algorithm>

#include "force_pipeline.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

using namespace scratch;

template <class Real>
Real ForcePipeline<Real>::finish_row(Real* ring, std::size_t row, Real* out, std::size_t span) {
  const std::size_t cols = cols_;
  const Real* __restrict inverse_mass = inverse_mass_ + row * cols;
  Real probe = 0;
  for (int k = 0; k < 3; ++k) {
    const Real* __restrict same = accumulator(ring, row, k, kSameColumn);
    const Real* __restrict next = accumulator(ring, row, k, kNextColumn);
    const Real* __restrict further = accumulator(ring, row, k, kFurtherColumn);
    Real* __restrict out_k = out + k * span;
    const Real g = gravity_[k];
#pragma omp simd reduction(+ : probe)
    for (std::size_t c = 0; c < cols; ++c) {
      const Real force = same[c] + next[c] + further[c];
      const Real value = inverse_mass[c] > Real(0) ? force * inverse_mass[c] + g : Real(0);
      out_k[c] = value;
      probe += value * Real(0);  // NaN exactly when value is not finite
    }
  }
  return probe;
}

template <class Real>
void ForcePipeline<Real>::recycle_row(Real* ring, std::size_t row) {
  for (int shift = 0; shift < static_cast<int>(kAccumulatorShifts); ++shift) {
    if (interior_row(row + (shift == kSameColumn ? 1 : 2))) continue;
    for (int k = 0; k < 3; ++k) std::fill_n(accumulator(ring, row, k, shift), cols_, Real(0));
  }
}

template <class Real>
void ForcePipeline<Real>::clear_accumulators(Real* ring) {
  // The ring's first rows, with their margins: the interior kernel's edge blocks read and write
  // there.
  std::fill_n(ring, kForceRowFrom * row_span_, Real(0));
}

template float ForcePipeline<float>::finish_row(float*, std::size_t, float*, std::size_t);
template double ForcePipeline<double>::finish_row(double*, std::size_t, double*, std::size_t);
template void ForcePipeline<float>::recycle_row(float*, std::size_t);
template void ForcePipeline<double>::recycle_row(double*, std::size_t);
template void ForcePipeline<float>::clear_accumulators(float*);
template void ForcePipeline<double>::clear_accumulators(double*);

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
