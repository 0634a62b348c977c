#include "force_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>

#include "gather_kernel.hpp"
#include "spring_kernel.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail {
namespace {

// Zeros left of column 0 in every ring row, so reads at c - 2 .. c + 1 need no branch.
constexpr std::size_t kMargin = 16;

std::size_t round_up_16(std::size_t value) { return (value + 15) / 16 * 16; }

// Ring slot of a row; rows down to -2 (the zero rows above the grid) are valid.
std::size_t slot(std::ptrdiff_t row) { return static_cast<std::size_t>((row + 3) % 3); }

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
    stage.offset = static_cast<std::size_t>(stencil_offset(stencil, scene.cols));
    stage.rest = static_cast<Real>(stencil_rest_length(scene, stencil));
    stage.ks = static_cast<Real>(family.ks);
    stage.kd = static_cast<Real>(family.kd);
    springs_per_eval_ += stage.count;
    damped_per_eval_ += stage.damped ? stage.count : 0;
    stages_.push_back(stage);
  }
  normals_per_eval_ = wind_ ? 2 * uint64_t{rows_ - 1} * (cols_ - 1) : 0;

  channels_ = stages_.size() + (wind_ ? 2 : 0);
  row_span_ = kMargin + round_up_16(cols_ + 1);
  ring_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * channels_ * 9 * row_span_);
}

template <class Real>
Real* ForcePipeline<Real>::row_buffer(int thread, std::size_t channel, std::ptrdiff_t row, int k) {
  const std::size_t ring_row =
      ((static_cast<std::size_t>(thread) * channels_ + channel) * 3 + slot(row)) * 3 +
      static_cast<std::size_t>(k);
  return ring_.data() + ring_row * row_span_ + kMargin;
}

template <class Real>
void ForcePipeline<Real>::compute_row(int thread, std::size_t row, Pass& pass) {
  const std::size_t first = row * cols_;
  for (std::size_t s = 0; s < stages_.size(); ++s) {
    const SpringStage& stage = stages_[s];
    if (row >= stage.extent.row_end) {  // no spring starts here: contribute zeros
      for (int k = 0; k < 3; ++k) std::fill_n(row_buffer(thread, s, row, k), cols_, Real(0));
      continue;
    }
    const bool damped = stage.damped && pass.v != nullptr;
    SpringRow<Real> job{};
    for (int k = 0; k < 3; ++k) {
      job.x[k] = pass.x + k * stride_ + first;
      job.v[k] = damped ? pass.v + k * stride_ + first : nullptr;
      job.f[k] = row_buffer(thread, s, row, k);
    }
    job.col_begin = stage.extent.col_begin;
    job.col_end = stage.extent.col_end;
    job.offset = stage.offset;
    job.rest = stage.rest;
    job.ks = stage.ks;
    job.kd = stage.kd;
    if (damped) {
      spring_row_forces<Real, true>(job);
    } else {
      spring_row_forces<Real, false>(job);
    }
  }
  if (!wind_) return;
  const bool timed = thread == 0;
  const auto start =
      timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  const std::size_t first_channel = stages_.size();
  if (row + 1 < rows_) {
    WindRow<Real> job{};
    for (int k = 0; k < 3; ++k) {
      job.x[k] = pass.x + k * stride_ + first;
      job.below[k] = job.x[k] + cols_;
      job.first[k] = row_buffer(thread, first_channel, row, k);
      job.second[k] = row_buffer(thread, first_channel + 1, row, k);
      job.direction[k] = wind_direction_[k];
    }
    job.cells = cols_ - 1;
    job.strength = wind_strength_;
    wind_row_forces(job);
  } else {  // the last row starts no cell
    for (std::size_t channel = first_channel; channel < channels_; ++channel) {
      for (int k = 0; k < 3; ++k) std::fill_n(row_buffer(thread, channel, row, k), cols_, Real(0));
    }
  }
  if (timed) {
    pass.wind_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

template <class Real>
void ForcePipeline<Real>::zero_row(int thread, std::ptrdiff_t row) {
  for (std::size_t channel = 0; channel < channels_; ++channel) {
    for (int k = 0; k < 3; ++k) std::fill_n(row_buffer(thread, channel, row, k), cols_, Real(0));
  }
}

template <class Real>
template <std::size_t M>
void ForcePipeline<Real>::gather_stages(int thread, std::ptrdiff_t row, int k, std::size_t first,
                                        bool assign, Real* out) {
  std::array<const Real*, M> own, back;
  for (std::size_t m = 0; m < M; ++m) {
    const SpringStage& stage = stages_[first + m];
    own[m] = row_buffer(thread, first + m, row, k);
    back[m] = row_buffer(thread, first + m, row - stage.row_step, k) - stage.col_step;
  }
  if (assign) {
    gather_springs<Real, M, true>(out, own, back, cols_);
  } else {
    gather_springs<Real, M, false>(out, own, back, cols_);
  }
}

template <class Real>
Real ForcePipeline<Real>::accumulate_row(int thread, std::size_t row, Real* a) {
  const auto r = static_cast<std::ptrdiff_t>(row);
  const std::size_t cols = cols_;
  const Real* __restrict inverse_mass = inverse_mass_ + row * cols;
  Real probe = 0;
  for (int k = 0; k < 3; ++k) {
    Real* __restrict out = a + k * stride_ + row * cols;
    bool assign = true;  // the first pass writes, later ones add
    for (std::size_t s = 0; s < stages_.size(); s += 3, assign = false) {
      switch (std::min<std::size_t>(3, stages_.size() - s)) {
        case 1:
          gather_stages<1>(thread, r, k, s, assign, out);
          break;
        case 2:
          gather_stages<2>(thread, r, k, s, assign, out);
          break;
        default:
          gather_stages<3>(thread, r, k, s, assign, out);
      }
    }
    if (wind_) {
      const std::size_t channel = stages_.size();
      const Real* first = row_buffer(thread, channel, r, k);
      const Real* second = row_buffer(thread, channel + 1, r, k);
      const Real* first_above = row_buffer(thread, channel, r - 1, k);
      const Real* second_above = row_buffer(thread, channel + 1, r - 1, k);
      if (assign) {
        gather_wind<Real, true>(out, first, second, first_above, second_above, cols);
      } else {
        gather_wind<Real, false>(out, first, second, first_above, second_above, cols);
      }
      assign = false;
    }
    if (assign) std::fill_n(out, cols, Real(0));  // no force but gravity
    const Real g = gravity_[k];
#pragma omp simd reduction(+ : probe)
    for (std::size_t c = 0; c < cols; ++c) {
      const Real value = inverse_mass[c] > Real(0) ? out[c] * inverse_mass[c] + g : Real(0);
      out[c] = value;
      probe += value * Real(0);  // NaN exactly when some value is not finite
    }
  }
  return probe;
}

template <class Real>
void ForcePipeline<Real>::run_rows(int thread, std::size_t begin, std::size_t end, Pass& pass,
                                   Real& probe) {
  // Rows above the block feed its first two rows: recompute them, or zero above the grid.
  for (std::ptrdiff_t row = static_cast<std::ptrdiff_t>(begin) - 2;
       row < static_cast<std::ptrdiff_t>(begin); ++row) {
    if (row < 0) {
      zero_row(thread, row);
    } else {
      compute_row(thread, static_cast<std::size_t>(row), pass);
    }
  }
  for (std::size_t row = begin; row < end; ++row) {
    compute_row(thread, row, pass);
    probe += accumulate_row(thread, row, pass.a);
  }
}

template <class Real>
bool ForcePipeline<Real>::evaluate(const Real* x, const Real* v, Real* a, StageCounters& counters) {
  const auto start = std::chrono::steady_clock::now();
  double wind_seconds = 0.0;
  Real probe = 0;
#pragma omp parallel num_threads(threads_) if (parallel_) reduction(+ : probe)
  {
    const int thread = omp_get_thread_num();
    const auto team = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t begin = rows_ * static_cast<std::size_t>(thread) / team;
    const std::size_t end = rows_ * static_cast<std::size_t>(thread + 1) / team;
    Pass pass{x, v, a, 0.0};
    run_rows(thread, begin, end, pass, probe);
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
