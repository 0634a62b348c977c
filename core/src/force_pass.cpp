// The force pass of ForcePipeline (force_pipeline.hpp): evaluate, a = M^-1 F(x, v). Each thread
// runs its block of rows once through the stages (staging, springs, wind, finish), after the
// two rows above the block whose springs and cells act on its first rows.
#include <omp.h>

#include <algorithm>
#include <chrono>

#include "force_pipeline.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
Real ForcePipeline<Real>::run_rows(int thread, std::size_t begin, std::size_t end,
                                   const StateCombination<Real>* const (&state)[2], Real* a,
                                   Pass& pass) {
  Real probe = 0;
  if (begin >= end) return probe;
  Real* const own = ring(thread, 0);
  // Springs and cells of the two rows above the block act on its first rows; their own
  // rows belong to another thread and are dropped.
  const std::size_t first = begin >= 2 ? begin - 2 : 0;
  std::size_t staged = first;
  // Where row r + 3 is a plain copy of the state, row r's interior sweeps stage it.
  const bool copies =
      col_pitch_ == 1 && state[0]->count == 0 && (state[1] == nullptr || state[1]->count == 0);
  clear_accumulators(own);
  for (std::size_t row = first; row < end; ++row) {
    // Rows r .. r + 2 staged before row r is run; row r + 3 reuses row r's slot.
    for (; staged < std::min(row + 3, rows_); ++staged) stage_row(thread, own, state, staged);
    if (copies && interior_row(row) && staged == row + 3 && staged < rows_ && row + 1 < end) {
      const std::size_t from = row_start(staged);
      const Real* const next[2] = {state[0]->base + from,
                                   pass.damped ? state[1]->base + from : nullptr};
      add_springs(own, row, pass, next);
      ++staged;
    } else {
      add_springs(own, row, pass);
    }
    add_wind(own, row, pass);
    if (row >= begin && col_pitch_ == 1) {
      probe += finish_row(own, row, a + row * cols_, stride_);
    } else if (row >= begin) {
      Real* finished = thread_row(thread, turned_from());
      probe += finish_row(own, row, finished, row_span_);
      scatter_row(finished, a, row);
    }
    recycle_row(own, row);
  }
  // What was added to the rows after the block belongs to the next thread's rows: dropped.
  return probe;
}

template <class Real>
bool ForcePipeline<Real>::evaluate(const StateCombination<Real>& x, const StateCombination<Real>* v,
                                   Real* a, StageCounters& counters) {
  const auto start = std::chrono::steady_clock::now();
  double wind_seconds = 0.0;
  Real probe = 0;
  const StateCombination<Real>* const state[2] = {&x, v};
  bool full_team = false;
#pragma omp parallel num_threads(threads_) if (parallel_) reduction(+ : probe)
  {
    const int thread = omp_get_thread_num();
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const auto t = static_cast<std::size_t>(thread);
    const Block block = block_of(t, team);
    if (thread == 0) full_team = block.balanced;
    const double pass_start = omp_get_wtime();
    Pass pass{v != nullptr, thread == 0, 0.0};
    probe += run_rows(thread, block.begin, block.end, state, a, pass);
    busy_[t] = omp_get_wtime() - pass_start;
    if (thread == 0) wind_seconds = pass.wind_seconds;
  }
  if (full_team) balance_split();
  // The pass is fused, so its time is split by thread 0's share of wind work.
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  wind_seconds = std::min(wind_seconds, seconds);
  counters.external_forces_s += wind_seconds;
  counters.internal_forces_s += seconds - wind_seconds;
  ++counters.force_evals;
  counters.springs_evaluated += springs_per_eval_;
  if (v != nullptr) counters.springs_damped += damped_per_eval_;
  counters.normals_computed += normals_per_eval_;
  return probe == Real(0);
}

template bool ForcePipeline<float>::evaluate(const StateCombination<float>&,
                                             const StateCombination<float>*, float*,
                                             StageCounters&);
template bool ForcePipeline<double>::evaluate(const StateCombination<double>&,
                                              const StateCombination<double>*, double*,
                                              StageCounters&);

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
