#include "force_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>

#include "shifted_add_kernel.hpp"
#include "spring_kernel.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail {
namespace {

// Zeros left of column 0 in every scratch row, so shifted reads need no branch.
constexpr std::size_t kMargin = 16;
// Accumulators, force row, wind rows, staged rows.
constexpr std::size_t kRowsPerThread = 9 + 3 + 6 + 18;
constexpr std::size_t kStagedRowsFrom = 18;

std::size_t round_up_16(std::size_t value) { return (value + 15) / 16 * 16; }

}  // namespace

template <class Real>
ForcePipeline<Real>::ForcePipeline(const Scene& scene, std::size_t stride, const Real* inverse_mass,
                                   bool velocity_forces, int threads, bool parallel)
    : rows_(scene.rows),
      cols_(scene.cols),
      stride_(stride),
      inverse_mass_(inverse_mass),
      threads_(threads),
      parallel_(parallel) {
  for (int k = 0; k < 3; ++k) {
    gravity_[k] = static_cast<Real>(scene.gravity[k]);
    wind_direction_[k] = static_cast<Real>(scene.wind_direction[k]);
  }
  wind_strength_ = static_cast<Real>(scene.wind_strength);
  wind_ = scene.has_wind() && rows_ > 1 && cols_ > 1;

  for (const Stencil& stencil : kProvotStencils) {
    const SpringFamily& family = scene.*stencil.family;
    SpringStage stage;
    stage.extent = stencil_extent(stencil, scene.rows, scene.cols);
    stage.count = stage.extent.count();
    stage.damped = velocity_forces && family.kd > 0.0;
    if (stage.count == 0 || (family.ks == 0.0 && !stage.damped)) continue;
    stage.row_step = stencil.row_step;
    stage.col_step = stencil.col_step;
    stage.rest = static_cast<Real>(stencil_rest_length(scene, stencil));
    stage.ks = static_cast<Real>(family.ks);
    stage.kd = static_cast<Real>(family.kd);
    springs_per_eval_ += stage.count;
    damped_per_eval_ += stage.damped ? stage.count : 0;
    stages_.push_back(stage);
  }
  normals_per_eval_ = wind_ ? 2 * uint64_t{rows_ - 1} * (cols_ - 1) : 0;

  row_span_ = kMargin + round_up_16(cols_ + 1);
  scratch_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * kRowsPerThread * row_span_);
}

template <class Real>
Real* ForcePipeline<Real>::accumulator(int thread, std::size_t row, int k) {
  const std::size_t index =
      static_cast<std::size_t>(thread) * kRowsPerThread + row % 3 * 3 + static_cast<std::size_t>(k);
  return scratch_.data() + index * row_span_ + kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::force_row(int thread, int k) {
  const std::size_t index =
      static_cast<std::size_t>(thread) * kRowsPerThread + 9 + static_cast<std::size_t>(k);
  return scratch_.data() + index * row_span_ + kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::wind_row(int thread, int triangle, int k) {
  const std::size_t index = static_cast<std::size_t>(thread) * kRowsPerThread + 12 +
                            static_cast<std::size_t>(triangle * 3 + k);
  return scratch_.data() + index * row_span_ + kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::staged_row(int thread, std::size_t row, int quantity, int k) {
  const std::size_t index = static_cast<std::size_t>(thread) * kRowsPerThread + kStagedRowsFrom +
                            row % 3 * 6 + static_cast<std::size_t>(quantity * 3 + k);
  return scratch_.data() + index * row_span_ + kMargin;
}

template <class Real>
const Real* ForcePipeline<Real>::state_row(int thread, const Pass& pass, int quantity,
                                           std::size_t row, int k) {
  const StateCombination<Real>& state = quantity == 0 ? *pass.x : *pass.v;
  if (state.count == 0) return state.base + k * stride_ + row * cols_;
  return staged_row(thread, row, quantity, k);
}

template <class Real>
void ForcePipeline<Real>::stage_row(int thread, const Pass& pass, std::size_t row) {
  for (int quantity = 0; quantity < 2; ++quantity) {
    const StateCombination<Real>* state = quantity == 0 ? pass.x : pass.v;
    if (state == nullptr || state->count == 0) continue;
    for (int k = 0; k < 3; ++k) {
      combine_row(staged_row(thread, row, quantity, k), *state, k * stride_ + row * cols_,
                  inverse_mass_ + row * cols_, cols_);
    }
  }
}

template <class Real>
void ForcePipeline<Real>::add_springs(int thread, std::size_t row, const Pass& pass) {
  for (const SpringStage& stage : stages_) {
    if (row >= stage.extent.row_end) continue;  // no spring of this stencil starts here
    const bool damped = stage.damped && pass.v != nullptr;
    const bool in_row = stage.row_step == 0;
    const std::size_t partner_row = row + stage.row_step;
    SpringRow<Real> job{};
    for (int k = 0; k < 3; ++k) {
      job.x[k] = state_row(thread, pass, 0, row, k);
      job.x_partner[k] = state_row(thread, pass, 0, partner_row, k) + stage.col_step;
      if (damped) {
        job.v[k] = state_row(thread, pass, 1, row, k);
        job.v_partner[k] = state_row(thread, pass, 1, partner_row, k) + stage.col_step;
      }
      job.own[k] = in_row ? force_row(thread, k) : accumulator(thread, row, k);
      job.partner[k] = accumulator(thread, partner_row, k) + stage.col_step;
    }
    job.col_begin = stage.extent.col_begin;
    job.col_end = stage.extent.col_end;
    job.rest = stage.rest;
    job.ks = stage.ks;
    job.kd = stage.kd;
    if (!in_row) {
      if (damped) {
        spring_row_forces<Real, true, true>(job);
      } else {
        spring_row_forces<Real, false, true>(job);
      }
      continue;
    }
    // In-row stencils start at column 0; the columns after the last spring must read 0.
    for (int k = 0; k < 3; ++k) std::fill(job.own[k] + job.col_end, job.own[k] + cols_, Real(0));
    if (damped) {
      spring_row_forces<Real, true, false>(job);
    } else {
      spring_row_forces<Real, false, false>(job);
    }
    const auto step = static_cast<std::size_t>(stage.col_step);
    for (int k = 0; k < 3; ++k) {
      add_row_springs(accumulator(thread, row, k), force_row(thread, k), step, cols_);
    }
  }
}

template <class Real>
void ForcePipeline<Real>::add_wind(int thread, std::size_t row, Pass& pass) {
  if (!wind_ || row + 1 >= rows_) return;  // the last row starts no cell
  const bool timed = thread == 0;
  const auto start =
      timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  WindRow<Real> job{};
  for (int k = 0; k < 3; ++k) {
    job.x[k] = state_row(thread, pass, 0, row, k);
    job.below[k] = state_row(thread, pass, 0, row + 1, k);
    job.first[k] = wind_row(thread, 0, k);
    job.second[k] = wind_row(thread, 1, k);
    job.direction[k] = wind_direction_[k];
  }
  job.cells = cols_ - 1;
  job.strength = wind_strength_;
  wind_row_forces(job);  // column cols - 1 has no cell and is never written: stays 0
  for (int k = 0; k < 3; ++k) {
    add_cell_winds(accumulator(thread, row, k), accumulator(thread, row + 1, k), job.first[k],
                   job.second[k], cols_);
  }
  if (timed) {
    pass.wind_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

template <class Real>
Real ForcePipeline<Real>::finish_row(int thread, std::size_t row, Real* a) {
  const std::size_t cols = cols_;
  const Real* __restrict inverse_mass = inverse_mass_ + row * cols;
  Real probe = 0;
  for (int k = 0; k < 3; ++k) {
    Real* __restrict acc = accumulator(thread, row, k);
    Real* __restrict out = a + k * stride_ + row * cols;
    const Real g = gravity_[k];
#pragma omp simd reduction(+ : probe)
    for (std::size_t c = 0; c < cols; ++c) {
      const Real value = inverse_mass[c] > Real(0) ? acc[c] * inverse_mass[c] + g : Real(0);
      out[c] = value;
      acc[c] = 0;                // ready for row + 3
      probe += value * Real(0);  // NaN exactly when value is not finite
    }
  }
  return probe;
}

template <class Real>
void ForcePipeline<Real>::clear_row(int thread, std::size_t row) {
  for (int k = 0; k < 3; ++k) std::fill_n(accumulator(thread, row, k), cols_, Real(0));
}

template <class Real>
Real ForcePipeline<Real>::run_rows(int thread, std::size_t begin, std::size_t end, Pass& pass) {
  Real probe = 0;
  if (begin >= end) return probe;
  // Springs and cells of the two rows above the block act on its first rows; their own
  // rows belong to another thread and are dropped.
  const std::size_t first = begin >= 2 ? begin - 2 : 0;
  std::size_t staged = first;
  // Rows r .. r + 2 staged before row r is run; row r + 3 reuses row r's slot.
  const auto stage_through = [&](std::size_t row) {
    for (; staged < std::min(row + 3, rows_); ++staged) stage_row(thread, pass, staged);
  };
  for (std::size_t row = first; row < begin; ++row) {
    stage_through(row);
    add_springs(thread, row, pass);
    add_wind(thread, row, pass);
    clear_row(thread, row);
  }
  for (std::size_t row = begin; row < end; ++row) {
    stage_through(row);
    add_springs(thread, row, pass);
    add_wind(thread, row, pass);
    probe += finish_row(thread, row, pass.a);
  }
  // Forces already added to the rows after the block belong to the next thread's rows.
  for (std::size_t row = end; row < std::min(end + 2, rows_); ++row) clear_row(thread, row);
  return probe;
}

template <class Real>
bool ForcePipeline<Real>::evaluate(const StateCombination<Real>& x, const StateCombination<Real>* v,
                                   Real* a, StageCounters& counters) {
  const auto start = std::chrono::steady_clock::now();
  double wind_seconds = 0.0;
  Real probe = 0;
#pragma omp parallel num_threads(threads_) if (parallel_) reduction(+ : probe)
  {
    const int thread = omp_get_thread_num();
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t begin = rows_ * static_cast<std::size_t>(thread) / team;
    const std::size_t end = rows_ * static_cast<std::size_t>(thread + 1) / team;
    Pass pass{&x, v, a, 0.0};
    probe += run_rows(thread, begin, end, pass);
    if (thread == 0) wind_seconds = pass.wind_seconds;
  }
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

template class ForcePipeline<float>;
template class ForcePipeline<double>;

}  // namespace clothlab::detail
