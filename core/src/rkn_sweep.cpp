// The fused Runge-Kutta-Nystrom step of ForcePipeline (declared in force_pipeline.hpp).
//
// Each thread sweeps its block of rows once; stage s works on row r while stage s - 1
// works on row r + 2, so every staged row a stage reads (r .. r + 2) is built from
// accelerations that are already final. Accelerations live in per-stage windows of
// 2 * stages rows, and the last stage's finished row is advanced in place at once: x and
// v cross memory once per step instead of once per stage and update.
//
// A block needs stage results from rows above and below it that only its own prelude can
// compute (2 rows per stage and side). Those rows of x and v belong to other threads,
// which overwrite them, so each thread copies them into its halo before a barrier.
#include <omp.h>

#include <algorithm>
#include <chrono>

#include "force_pipeline.hpp"
#include "simd_namespace.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
Real ForcePipeline<Real>::rkn_rows(int thread, std::size_t begin, std::size_t end, Real* x, Real* v,
                                   const RknStep<Real>& step, Pass& pass) {
  Real probe = 0;
  if (begin >= end) return probe;
  const std::size_t stages = step.stages;
  // Per stage: rows run from `first` (up to two prelude rows that only feed the rows
  // below), finished from `ready`, through `last`; `staged` is the next row to stage.
  std::size_t first[RknStep<Real>::kMaxStages] = {}, ready[RknStep<Real>::kMaxStages] = {};
  std::size_t last[RknStep<Real>::kMaxStages] = {}, staged[RknStep<Real>::kMaxStages] = {};
  for (std::size_t s = 0; s < stages; ++s) {
    const std::size_t ahead = 2 * (stages - 1 - s);
    ready[s] = begin > ahead ? begin - ahead : 0;
    first[s] = ready[s] > 2 ? ready[s] - 2 : 0;
    last[s] = std::min(rows_ - 1, end - 1 + ahead);
    staged[s] = first[s];
    clear_accumulators(ring(thread, s));
  }
  // Component k of row `row` of x (quantity 0) or v (1): in place in the block (of a turned
  // grid: its copy, gathered by stage_rkn_row), else halo.
  const bool turned = col_pitch_ != 1;
  const auto source = [&](int quantity, std::size_t row, std::size_t k) -> const Real* {
    if (row < begin || row >= end)
      return halo_row(thread, halo_slot(row, begin, end, stages), quantity) + k * row_span_;
    if (turned) return thread_row(thread, turned_from() + 3 * quantity) + k * row_span_;
    return (quantity == 0 ? x : v) + k * stride_ + row * cols_;
  };
  const auto stage_rkn_row = [&](std::size_t s, std::size_t row) {
    Real* const stage_ring = ring(thread, s);
    if (turned && row >= begin && row < end) {
      gather_row(x, row, thread_row(thread, turned_from()));
      gather_row(v, row, thread_row(thread, turned_from() + 3));
    }
    for (std::size_t k = 0; k < 3; ++k) {
      Real x_weights[RknStep<Real>::kMaxStages + 1], v_weights[RknStep<Real>::kMaxStages];
      const Real* x_terms[RknStep<Real>::kMaxStages + 1];
      const Real* v_terms[RknStep<Real>::kMaxStages];
      uint32_t x_count = 0, v_count = 0;
      if (step.x_velocity[s] != Real(0)) {
        x_weights[x_count] = step.x_velocity[s];
        x_terms[x_count++] = source(1, row, k);
      }
      for (std::size_t j = 0; j < s; ++j) {
        const Real* a = window_row(thread, j, row) + k * row_span_;
        if (step.x_stage[s][j] != Real(0)) {
          x_weights[x_count] = step.x_stage[s][j];
          x_terms[x_count++] = a;
        }
        if (step.v_stage[s][j] != Real(0)) {
          v_weights[v_count] = step.v_stage[s][j];
          v_terms[v_count++] = a;
        }
      }
      const Real* inverse_mass = inverse_mass_ + row * cols_;
      combine_row(staged_row(stage_ring, row, 0, static_cast<int>(k)), source(0, row, k), x_count,
                  x_weights, x_terms, inverse_mass, cols_);
      combine_row(staged_row(stage_ring, row, 1, static_cast<int>(k)), source(1, row, k), v_count,
                  v_weights, v_terms, inverse_mass, cols_);
    }
  };
  // x += h v + sum_s x_weights[s] A_s, v += sum_s v_weights[s] A_s on active particles.
  const auto advance_row = [&](std::size_t row) {
    Real* __restrict dx = thread_row(thread, scratch::update_from(reserved_stages_));
    Real* __restrict dv = thread_row(thread, scratch::update_from(reserved_stages_) + 1);
    const Real* __restrict inverse_mass = inverse_mass_ + row * cols_;
    const Real h = step.h;
    const std::size_t pitch = col_pitch_;
    for (std::size_t k = 0; k < 3; ++k) {
      Real* __restrict xr = x + k * stride_ + row_start(row);
      Real* __restrict vr = v + k * stride_ + row_start(row);
      if (turned) {
        for (std::size_t c = 0; c < cols_; ++c) dx[c] = h * vr[c * pitch];
        std::fill_n(dv, cols_, Real(0));
      } else {
#pragma omp simd
        for (std::size_t c = 0; c < cols_; ++c) {
          dx[c] = h * vr[c];
          dv[c] = 0;
        }
      }
      for (std::size_t s = 0; s < stages; ++s) {
        const Real* __restrict a = window_row(thread, s, row) + k * row_span_;
        const Real wx = step.x_weights[s], wv = step.v_weights[s];
#pragma omp simd
        for (std::size_t c = 0; c < cols_; ++c) {
          dx[c] += wx * a[c];
          dv[c] += wv * a[c];
        }
      }
      if (turned) {
        for (std::size_t c = 0; c < cols_; ++c) {
          const bool active = inverse_mass[c] > Real(0);
          xr[c * pitch] += active ? dx[c] : Real(0);
          vr[c * pitch] += active ? dv[c] : Real(0);
        }
      } else {
#pragma omp simd
        for (std::size_t c = 0; c < cols_; ++c) {
          const bool active = inverse_mass[c] > Real(0);
          xr[c] += active ? dx[c] : Real(0);
          vr[c] += active ? dv[c] : Real(0);
        }
      }
    }
  };

  const std::size_t last_tick = end - 1 + 2 * (stages - 1);
  for (std::size_t tick = first[0]; tick <= last_tick; ++tick) {
    for (std::size_t s = 0; s < stages; ++s) {
      if (tick < first[s] + 2 * s || tick - 2 * s > last[s]) continue;
      const std::size_t row = tick - 2 * s;
      Real* const stage_ring = ring(thread, s);
      for (; staged[s] < std::min(row + 3, rows_); ++staged[s]) stage_rkn_row(s, staged[s]);
      add_springs(stage_ring, row, pass);
      add_wind(stage_ring, row, pass);
      if (row >= ready[s]) {
        probe += finish_row(stage_ring, row, window_row(thread, s, row), row_span_);
        if (s == stages - 1) advance_row(row);
      }
      recycle_row(stage_ring, row);
    }
  }
  // What was added to rows after a stage's last one belongs to rows not run here: dropped.
  return probe;
}

template <class Real>
bool ForcePipeline<Real>::step_rkn(Real* x, Real* v, const RknStep<Real>& step,
                                   StageCounters& counters) {
  const auto start = std::chrono::steady_clock::now();
  Real probe = 0;
  bool full_team = false;
#pragma omp parallel num_threads(threads_) if (parallel_) reduction(+ : probe)
  {
    const int thread = omp_get_thread_num();
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const auto t = static_cast<std::size_t>(thread);
    const Block block = block_of(t, team);
    const std::size_t begin = block.begin, end = block.end;
    if (thread == 0) full_team = block.balanced;
    // Halo: rows of x and v the prelude reads above and below the block.
    const std::size_t reach = 2 * step.stages;
    const std::size_t above = begin > reach ? begin - reach : 0;
    const std::size_t below = std::min(rows_, end + reach);
    const auto copy_row = [&](std::size_t row) {
      const std::size_t slot = halo_slot(row, begin, end, step.stages);
      gather_row(x, row, halo_row(thread, slot, 0));
      gather_row(v, row, halo_row(thread, slot, 1));
    };
    for (std::size_t row = above; row < begin; ++row) copy_row(row);
    for (std::size_t row = end; row < below; ++row) copy_row(row);
#pragma omp barrier
    const double sweep_start = omp_get_wtime();
    Pass pass{true, false, 0.0};
    probe += rkn_rows(thread, begin, end, x, v, step, pass);
    busy_[t] = omp_get_wtime() - sweep_start;
  }
  if (full_team) balance_split();
  // Springs, wind and the updates run interleaved: the whole sweep counts as forces.
  counters.internal_forces_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  counters.force_evals += step.stages;
  counters.springs_evaluated += step.stages * springs_per_eval_;
  counters.springs_damped += step.stages * damped_per_eval_;
  counters.normals_computed += step.stages * normals_per_eval_;
  return probe == Real(0);
}

template bool ForcePipeline<float>::step_rkn(float*, float*, const RknStep<float>&, StageCounters&);
template bool ForcePipeline<double>::step_rkn(double*, double*, const RknStep<double>&,
                                              StageCounters&);

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
