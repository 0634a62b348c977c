// The external pass of ForcePipeline (declared in force_pipeline.hpp): gravity and wind
// alone, for the host's external-forces extension.
//
// Each thread runs its block of rows once. A row's cells (the wind shares of their two
// triangles) are computed once into a ring of two cell rows, reading the positions in
// place; the row's particles then sum the shares of the cells beside and above them
// (external_row_kernel.hpp). (In its own file: beside the force evaluation it cost that
// pass the inlining of its interior kernel.)
#include <omp.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "external_row_kernel.hpp"
#include "force_pipeline.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail {

using namespace scratch;

template <class Real>
Real* ForcePipeline<Real>::cell_shares(Real* scratch, std::ptrdiff_t q, int triangle) const {
  const auto t = static_cast<std::size_t>(triangle);
  if (!wind_ || q < 0 || static_cast<std::size_t>(q) + 1 >= rows_)
    return external_row(scratch, kZeroCellRowsFrom + 3 * t);
  return external_row(scratch, kCellRowsFrom + static_cast<std::size_t>(q) % 2 * 6 + 3 * t);
}

template <class Real>
void ForcePipeline<Real>::compute_cells(Real* scratch, const Real* x, std::size_t q) {
  if (!wind_ || q + 1 >= rows_) return;
  WindRow<Real> job{};
  if (col_pitch_ == 1) {
    job.x = x + row_start(q);
    job.below = x + row_start(q + 1);
    job.position_span = stride_;
  } else {
    Real* upper = external_row(scratch, kExternalPositionsFrom);
    Real* lower = external_row(scratch, kExternalPositionsFrom + 3);
    gather_row(x, q, upper);
    gather_row(x, q + 1, lower);
    job.x = upper;
    job.below = lower;
    job.position_span = row_span_;
  }
  const auto cell_row = static_cast<std::ptrdiff_t>(q);
  job.first = cell_shares(scratch, cell_row, 0);
  job.second = cell_shares(scratch, cell_row, 1);
  job.span = row_span_;
  for (int k = 0; k < 3; ++k) job.direction[k] = wind_direction_[k];
  job.cells = cols_ - 1;
  job.strength = wind_strength_;
  wind_row_forces(job);  // column cols - 1 has no cell and is never written: stays 0
}

template <class Real>
Real ForcePipeline<Real>::finish_external_row(Real* scratch, std::size_t row, Real* out,
                                              std::size_t out_span) {
  const auto above = static_cast<std::ptrdiff_t>(row) - 1, own = above + 1;
  ExternalRow<Real> job{};
  job.first_above = cell_shares(scratch, above, 0);
  job.second_above = cell_shares(scratch, above, 1);
  job.first_own = cell_shares(scratch, own, 0);
  job.second_own = cell_shares(scratch, own, 1);
  job.share_span = row_span_;
  job.inverse_mass = inverse_mass_ + row * cols_;
  job.out = out;
  job.out_span = out_span;
  job.cols = cols_;
  for (int k = 0; k < 3; ++k) job.gravity[k] = gravity_[k];
  return external_row_accelerations(job);
}

template <class Real>
Real ForcePipeline<Real>::finish_external_row(Real* scratch, std::size_t row, Real* a) {
  if (col_pitch_ == 1) return finish_external_row(scratch, row, a + row_start(row), stride_);
  Real* finished = external_row(scratch, kExternalFinishedFrom);
  const Real probe = finish_external_row(scratch, row, finished, row_span_);
  scatter_row(finished, a, row);
  return probe;
}

// A row needs the cells of its row and of the row above: the ring keeps the last two.
template <class Real>
Real ForcePipeline<Real>::external_rows(Real* scratch, std::size_t begin, std::size_t end,
                                        const Real* x, Real* a) {
  Real probe = 0;
  if (begin >= end) return probe;
  if (begin > 0) compute_cells(scratch, x, begin - 1);
  for (std::size_t row = begin; row < end; ++row) {
    compute_cells(scratch, x, row);
    probe += finish_external_row(scratch, row, a);
  }
  return probe;
}

template <class Real>
bool ForcePipeline<Real>::evaluate_external(const Real* x, Real* a) {
  Real probe = 0;
#pragma omp parallel num_threads(threads_) if (parallel_) reduction(+ : probe)
  {
    const int thread = omp_get_thread_num();
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const Block block = block_of(static_cast<std::size_t>(thread), team);
    probe += external_rows(thread_external_scratch(thread), block.begin, block.end, x, a);
  }
  return probe == Real(0);
}

template <class Real>
std::size_t ForcePipeline<Real>::range_workspace_elements() const {
  const std::size_t rows = kCursorElements + kExternalRows * row_span_;
  return col_pitch_ == 1 ? rows : rows + 3 * stride_;
}

// Rows in place: each cell row is computed once per sequence however the rows are split
// into ranges, in either direction (the ring slot of cell row q is q % 2). A turned grid's
// pipeline rows are the state's columns: there the sequence's first call runs the pass.
template <class Real>
bool ForcePipeline<Real>::evaluate_external_range(const Real* x, Real* a, std::size_t first,
                                                  std::size_t count, Real* workspace, bool resume) {
  auto& cursor = *reinterpret_cast<RangeCursor*>(workspace);
  Real* const scratch = workspace + kCursorElements;
  if (count == 0) return true;
  Real probe = 0;
  const auto copy_range = [&](const Real* from, std::size_t begin, std::size_t length) {
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = begin; i < begin + length; ++i) {
        a[k * stride_ + i] = from[k * stride_ + i];
        probe += a[k * stride_ + i] * Real(0);
      }
  };
  if (col_pitch_ != 1) {
    Real* const whole = scratch + kExternalRows * row_span_;
    if (!resume) (void)external_rows(scratch, 0, rows_, x, whole);
    copy_range(whole, first, count);
    return probe == Real(0);
  }
  if (!resume) cursor.held[0] = cursor.held[1] = -1;
  const auto ensure_cells = [&](std::ptrdiff_t q) {
    if (q < 0 || static_cast<std::size_t>(q) + 1 >= rows_) return;
    int64_t& held = cursor.held[q % 2];
    if (held == q) return;
    compute_cells(scratch, x, static_cast<std::size_t>(q));
    held = q;
  };
  const std::size_t end = first + count;
  for (std::size_t row = first / cols_; row * cols_ < end; ++row) {
    ensure_cells(static_cast<std::ptrdiff_t>(row) - 1);
    ensure_cells(static_cast<std::ptrdiff_t>(row));
    const std::size_t row_begin = row * cols_, row_end = row_begin + cols_;
    if (first <= row_begin && row_end <= end) {
      probe += finish_external_row(scratch, row, a + row_begin, stride_);
      continue;
    }
    Real* finished = external_row(scratch, kExternalFinishedFrom);
    (void)finish_external_row(scratch, row, finished, row_span_);
    const std::size_t begin = std::max(first, row_begin), stop = std::min(end, row_end);
    for (std::size_t k = 0; k < 3; ++k)
      for (std::size_t i = begin; i < stop; ++i) {
        a[k * stride_ + i] = finished[k * row_span_ + (i - row_begin)];
        probe += a[k * stride_ + i] * Real(0);
      }
  }
  return probe == Real(0);
}

template bool ForcePipeline<float>::evaluate_external(const float*, float*);
template bool ForcePipeline<double>::evaluate_external(const double*, double*);
template std::size_t ForcePipeline<float>::range_workspace_elements() const;
template std::size_t ForcePipeline<double>::range_workspace_elements() const;
template bool ForcePipeline<float>::evaluate_external_range(const float*, float*, std::size_t,
                                                            std::size_t, float*, bool);
template bool ForcePipeline<double>::evaluate_external_range(const double*, double*, std::size_t,
                                                             std::size_t, double*, bool);

}  // namespace clothlab::detail
