// The staging stage of ForcePipeline (force_pipeline.hpp): copies between the state and the
// scratch rows. A grid row of x and v goes into the staged rows (for a stage of a
// multi-stage method formed there as a combination); whole rows are gathered into scratch rows
// (halo, a turned grid's columns) and finished rows scattered back.
#include <algorithm>

#include "force_pipeline.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
void ForcePipeline<Real>::stage_row(int thread, Real* ring,
                                    const StateCombination<Real>* const (&state)[2],
                                    std::size_t row) {
  for (int quantity = 0; quantity < 2; ++quantity) {
    if (state[quantity] == nullptr) continue;
    const StateCombination<Real>& sum = *state[quantity];
    for (int k = 0; k < 3; ++k) {
      const std::size_t first = k * stride_ + row_start(row);
      const Real* vectors[StateCombination<Real>::kMaxTerms];
      const Real* base = sum.base + first;
      for (uint32_t term = 0; term < sum.count; ++term) vectors[term] = sum.vectors[term] + first;
      if (col_pitch_ != 1) {
        // A turned grid's row is a column of the state: contiguous copies of it go through
        // the same kernel, so the sums are the same, bit for bit.
        Real* copy = thread_row(thread, turned_from() + 6);
        gather_component(base, copy);
        base = copy;
        for (uint32_t term = 0; term < sum.count; ++term) {
          copy = thread_row(thread, turned_from() + 7 + term);
          gather_component(vectors[term], copy);
          vectors[term] = copy;
        }
      }
      combine_row(staged_row(ring, row, quantity, k), base, sum.count, sum.coefficients, vectors,
                  inverse_mass_ + row * cols_, cols_);
    }
  }
}

template <class Real>
void ForcePipeline<Real>::gather_component(const Real* from, Real* to) const {
  for (std::size_t c = 0; c < cols_; ++c) to[c] = from[c * col_pitch_];
}

template <class Real>
void ForcePipeline<Real>::gather_row(const Real* state, std::size_t row, Real* to) const {
  const Real* from = state + row_start(row);
  for (std::size_t k = 0; k < 3; ++k) {
    if (col_pitch_ == 1) {
      std::copy_n(from + k * stride_, cols_, to + k * row_span_);
    } else {
      gather_component(from + k * stride_, to + k * row_span_);
    }
  }
}

template <class Real>
void ForcePipeline<Real>::scatter_row(const Real* from, Real* state, std::size_t row) const {
  Real* to = state + row_start(row);
  for (std::size_t k = 0; k < 3; ++k)
    for (std::size_t c = 0; c < cols_; ++c)
      to[k * stride_ + c * col_pitch_] = from[k * row_span_ + c];
}

template void ForcePipeline<float>::stage_row(int, float*, StatePair, std::size_t);
template void ForcePipeline<double>::stage_row(int, double*, StatePair, std::size_t);
template void ForcePipeline<float>::gather_row(const float*, std::size_t, float*) const;
template void ForcePipeline<double>::gather_row(const double*, std::size_t, double*) const;
template void ForcePipeline<float>::scatter_row(const float*, float*, std::size_t) const;
template void ForcePipeline<double>::scatter_row(const double*, double*, std::size_t) const;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
