// The external pass of ForcePipeline (declared in force_pipeline.hpp): gravity, wind and air
// alone, for the host's external-forces extension.
//
// Each thread runs its block of rows once. A row's cells (the wind and air shares of their two
// triangles) are computed once into a ring of two cell rows, reading the positions in
// place; the row's particles then sum the shares of the cells beside and above them
// (external_row_kernel.hpp). (Kept out of spring_stage.cpp: beside it, the spring stage lost
// the inlining of its interior kernel.)
#include <omp.h>

#include <algorithm>
#include <cstddef>

#include "external_row_kernel.hpp"
#include "force_pipeline.hpp"
#include "simd_namespace.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

using namespace scratch;

template <class Real>
Real* ForcePipeline<Real>::cell_shares(int thread, std::ptrdiff_t q, int triangle) {
  const auto t = static_cast<std::size_t>(triangle);
  if (!cell_forces_ || q < 0 || static_cast<std::size_t>(q) + 1 >= rows_)
    return external_row(thread, kZeroCellRowsFrom + 3 * t);
  return external_row(thread, kCellRowsFrom + static_cast<std::size_t>(q) % 2 * 6 + 3 * t);
}

template <class Real>
void ForcePipeline<Real>::compute_cells(int thread, const Real* x, const Real* v, std::size_t q) {
  if (!cell_forces_ || q + 1 >= rows_) return;
  WindRow<Real> job{};
  const Real *velocity = nullptr, *velocity_below = nullptr;
  if (col_pitch_ == 1) {
    job.x = x + row_start(q);
    job.below = x + row_start(q + 1);
    job.position_span = stride_;
    if (air_ && v != nullptr) {
      velocity = v + row_start(q);
      velocity_below = v + row_start(q + 1);
    }
  } else {
    Real* upper = external_row(thread, kExternalPositionsFrom);
    Real* lower = external_row(thread, kExternalPositionsFrom + 3);
    gather_row(x, q, upper);
    gather_row(x, q + 1, lower);
    job.x = upper;
    job.below = lower;
    job.position_span = row_span_;
    if (air_ && v != nullptr) {
      Real* upper_velocity = external_row(thread, kExternalVelocitiesFrom);
      Real* lower_velocity = external_row(thread, kExternalVelocitiesFrom + 3);
      gather_row(v, q, upper_velocity);
      gather_row(v, q + 1, lower_velocity);
      velocity = upper_velocity;
      velocity_below = lower_velocity;
    }
  }
  const auto cell_row = static_cast<std::ptrdiff_t>(q);
  job.first = cell_shares(thread, cell_row, 0);
  job.second = cell_shares(thread, cell_row, 1);
  job.span = row_span_;
  for (int k = 0; k < 3; ++k) job.direction[k] = wind_direction_[k];
  job.cells = cols_ - 1;
  job.strength = wind_strength_;
  if (wind_) {
    wind_row_forces(job);  // column cols - 1 has no cell and is never written: stays 0
  } else {
    for (int k = 0; k < 3; ++k) {
      std::fill_n(job.first + k * row_span_, job.cells, Real(0));
      std::fill_n(job.second + k * row_span_, job.cells, Real(0));
    }
  }
  if (air_)
    add_air(job.x, job.below, velocity, velocity_below, job.position_span, job.first, job.second,
            row_span_);
}

template <class Real>
Real ForcePipeline<Real>::finish_external_row(int thread, std::size_t row, Real* a) {
  const auto above = static_cast<std::ptrdiff_t>(row) - 1, own = above + 1;
  const bool in_place = col_pitch_ == 1;
  ExternalRow<Real> job{};
  job.first_above = cell_shares(thread, above, 0);
  job.second_above = cell_shares(thread, above, 1);
  job.first_own = cell_shares(thread, own, 0);
  job.second_own = cell_shares(thread, own, 1);
  job.share_span = row_span_;
  job.inverse_mass = inverse_mass_ + row * cols_;
  job.out = in_place ? a + row_start(row) : external_row(thread, kExternalFinishedFrom);
  job.out_span = in_place ? stride_ : row_span_;
  job.cols = cols_;
  for (int k = 0; k < 3; ++k) job.gravity[k] = gravity_[k];
  const Real probe = external_row_accelerations(job);
  if (!in_place) scatter_row(job.out, a, row);
  return probe;
}

// A row needs the cells of its row and of the row above: the ring keeps the last two, going
// up from `begin` or (backward) down from `end`.
template <class Real>
Real ForcePipeline<Real>::external_rows(int thread, std::size_t begin, std::size_t end,
                                        const Real* x, const Real* v, Real* a, bool backward) {
  Real probe = 0;
  if (begin >= end) return probe;
  if (backward) {
    compute_cells(thread, x, v, end - 1);
    for (std::size_t row = end; row-- > begin;) {
      if (row > 0) compute_cells(thread, x, v, row - 1);
      probe += finish_external_row(thread, row, a);
    }
    return probe;
  }
  if (begin > 0) compute_cells(thread, x, v, begin - 1);
  for (std::size_t row = begin; row < end; ++row) {
    compute_cells(thread, x, v, row);
    probe += finish_external_row(thread, row, a);
  }
  return probe;
}

template <class Real>
bool ForcePipeline<Real>::evaluate_external(const Real* x, const Real* v, Real* a) {
  Real probe = 0;
#pragma omp parallel num_threads(threads_) if (parallel_) reduction(+ : probe)
  {
    const int thread = omp_get_thread_num();
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const Block block = block_of(static_cast<std::size_t>(thread), team);
    // Each block ends at the grid's nearer edge, where a sweep over the rows that reads a
    // next starts (from row 0, or from both edges): those rows are still in cache.
    probe +=
        external_rows(thread, block.begin, block.end, x, v, a, block.begin + block.end <= rows_);
  }
  return probe == Real(0);
}

template <class Real>
bool ForcePipeline<Real>::evaluate_external_rows(int slot, std::size_t begin, std::size_t end,
                                                 const Real* x, const Real* v, Real* a) {
  return external_rows(slot, begin, end, x, v, a, false) == Real(0);
}

template bool ForcePipeline<float>::evaluate_external_rows(int, std::size_t, std::size_t,
                                                           const float*, const float*, float*);
template bool ForcePipeline<double>::evaluate_external_rows(int, std::size_t, std::size_t,
                                                            const double*, const double*, double*);
template bool ForcePipeline<float>::evaluate_external(const float*, const float*, float*);
template bool ForcePipeline<double>::evaluate_external(const double*, const double*, double*);

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
