#include "force_pipeline.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <type_traits>

#include "interior_row_kernel.hpp"
#include "scratch_layout.hpp"
#include "shifted_add_kernel.hpp"
#include "spring_kernel.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail {
namespace {

using namespace scratch;

#if defined(__AVX512F__)
constexpr bool kInteriorKernel = true;
#else
constexpr bool kInteriorKernel = false;
#endif

std::size_t round_up_16(std::size_t value) { return (value + 15) / 16 * 16; }

}  // namespace

template <class Real>
ForcePipeline<Real>::ForcePipeline(const Scene& scene, std::size_t stride, const Real* inverse_mass,
                                   bool velocity_forces, int threads, bool parallel,
                                   std::size_t col_pitch)
    : rows_(scene.rows),
      cols_(scene.cols),
      stride_(stride),
      col_pitch_(col_pitch),
      inverse_mass_(inverse_mass),
      threads_(threads),
      parallel_(parallel) {
  if (col_pitch_ != 1) {
    turned_inverse_mass_ = AlignedBuffer<Real>(rows_ * cols_);
    for (std::size_t r = 0; r < rows_; ++r)
      for (std::size_t c = 0; c < cols_; ++c)
        turned_inverse_mass_[r * cols_ + c] = inverse_mass[r + c * col_pitch_];
    inverse_mass_ = turned_inverse_mass_.data();
  }
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

  interior_kernel_ = kInteriorKernel && std::is_same_v<Real, float> && stages_.size() == 6;
  row_span_ = kMargin + round_up_16(cols_ + kMargin + 2);
  reserve_stages(1);
  for (std::size_t t = 0; t <= static_cast<std::size_t>(threads_); ++t) {
    split_.push_back(rows_ * t / static_cast<std::size_t>(threads_));
  }
  busy_.assign(static_cast<std::size_t>(threads_), 0.0);
  const std::size_t gap = kGapBytes / sizeof(Real);
  external_stride_ = (kExternalRows * row_span_ + gap - 1) / gap * gap + gap;
  external_scratch_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * external_stride_);
}

template <class Real>
void ForcePipeline<Real>::reserve_stages(uint32_t stages) {
  if (stages <= reserved_stages_) return;
  reserved_stages_ = stages;
  // Per thread: a ring per stage, then for the fused step an acceleration ring per stage,
  // the halo rows and two update rows (see rkn_sweep.cpp).
  const std::size_t rows = turned_from() + 7 + StateCombination<Real>::kMaxTerms;
  // Each thread's scratch starts 64 KiB after the end of the previous one's: closer, the
  // second thread ran slower (likely prefetch or cache-set sharing between the cores' hot
  // rows; docs/performance.md, "What made it fast").
  const std::size_t gap = kGapBytes / sizeof(Real);
  thread_stride_ = (rows * row_span_ + gap - 1) / gap * gap + gap;
  scratch_ = AlignedBuffer<Real>(static_cast<std::size_t>(threads_) * thread_stride_);
}

template <class Real>
Real* ForcePipeline<Real>::ring(int thread, std::size_t stage) {
  return scratch_.data() + static_cast<std::size_t>(thread) * thread_stride_ +
         stage * kRowsPerRing * row_span_;
}

template <class Real>
Real* ForcePipeline<Real>::thread_row(int thread, std::size_t index) {
  return scratch_.data() + static_cast<std::size_t>(thread) * thread_stride_ + index * row_span_ +
         kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::accumulator(Real* ring, std::size_t row, int k, int shift) {
  const std::size_t index = (row % 3 * kAccumulatorShifts + static_cast<std::size_t>(shift)) * 3 +
                            static_cast<std::size_t>(k);
  return ring + index * row_span_ + kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::force_row(Real* ring, int k) {
  return ring + (kForceRowFrom + static_cast<std::size_t>(k)) * row_span_ + kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::wind_row(Real* ring, int triangle, int k) {
  return ring + (kWindRowsFrom + static_cast<std::size_t>(triangle * 3 + k)) * row_span_ + kMargin;
}

template <class Real>
Real* ForcePipeline<Real>::staged_row(Real* ring, std::size_t row, int quantity, int k) {
  const std::size_t index =
      kStagedRowsFrom + row % 3 * 6 + static_cast<std::size_t>(quantity * 3 + k);
  return ring + index * row_span_ + kMargin;
}

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

template <class Real>
void ForcePipeline<Real>::add_springs(Real* ring, std::size_t row, const Pass& pass) {
  if (interior_row(row)) {
    add_interior_springs(ring, row, pass);
    return;
  }
  for (const SpringStage& stage : stages_) {
    if (row >= stage.extent.row_end) continue;  // no spring of this stencil starts here
    const bool damped = stage.damped && pass.damped;
    const bool in_row = stage.row_step == 0;
    const std::size_t partner_row = row + stage.row_step;
    SpringRow<Real> job{};
    job.x = staged_row(ring, row, 0, 0);
    job.x_partner = staged_row(ring, partner_row, 0, 0) + stage.col_step;
    if (damped) {
      job.v = staged_row(ring, row, 1, 0);
      job.v_partner = staged_row(ring, partner_row, 1, 0) + stage.col_step;
    }
    job.own = in_row ? force_row(ring, 0) : accumulator(ring, row, 0);
    job.partner = accumulator(ring, partner_row, 0) + stage.col_step;
    job.span = row_span_;
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
    for (int k = 0; k < 3; ++k) {
      Real* force = force_row(ring, k);
      std::fill(force + job.col_end, force + cols_, Real(0));
    }
    if (damped) {
      spring_row_forces<Real, true, false>(job);
    } else {
      spring_row_forces<Real, false, false>(job);
    }
    const auto step = static_cast<std::size_t>(stage.col_step);
    for (int k = 0; k < 3; ++k) {
      add_row_springs(accumulator(ring, row, k), force_row(ring, k), step, cols_);
    }
  }
}

template <class Real>
void ForcePipeline<Real>::add_interior_springs(Real* ring, std::size_t row, const Pass& pass) {
#if defined(__AVX512F__)
  if constexpr (std::is_same_v<Real, float>) {
    InteriorRow job{};
    bool damped = false;
    for (std::size_t r = 0; r < 3; ++r) {
      job.x[r] = staged_row(ring, row + r, 0, 0);
      job.v[r] = pass.damped ? staged_row(ring, row + r, 1, 0) : nullptr;
      job.aligned[r] = accumulator(ring, row + r, 0, kSameColumn);
    }
    job.plus1[0] = accumulator(ring, row, 0, kNextColumn);
    job.plus1[1] = accumulator(ring, row + 1, 0, kNextColumn);
    job.minus1 = accumulator(ring, row + 1, 0, kFurtherColumn);
    job.plus2 = accumulator(ring, row, 0, kFurtherColumn);
    job.span = row_span_;
    job.cols = cols_;
    for (std::size_t s = 0; s < 6; ++s) {
      const SpringStage& stage = stages_[s];
      const bool stage_damped = stage.damped && pass.damped;
      job.rest[s] = stage.rest;
      job.ks[s] = stage.ks;
      job.kd[s] = stage_damped ? stage.kd : 0.0f;  // one damped sweep; undamped ones add 0
      damped = damped || stage_damped;
    }
    for (int k = 0; k < 3; ++k) job.wind_direction[k] = _mm512_set1_ps(wind_direction_[k]);
    job.wind_strength_sixth = _mm512_set1_ps(wind_strength_ / 6.0f);
    if (damped) {
      if (wind_) {
        interior_row_forces<true, true>(job);
      } else {
        interior_row_forces<true, false>(job);
      }
    } else if (wind_) {
      interior_row_forces<false, true>(job);
    } else {
      interior_row_forces<false, false>(job);
    }
    return;
  }
#endif
  (void)ring, (void)row, (void)pass;  // only float on AVX-512 has the interior kernel
}

template <class Real>
void ForcePipeline<Real>::add_wind(Real* ring, std::size_t row, Pass& pass) {
  if (!wind_ || row + 1 >= rows_) return;  // the last row starts no cell
  if (interior_row(row)) return;           // its cells went with its springs
  const bool timed = pass.timed;
  const auto start =
      timed ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{};
  WindRow<Real> job{};
  job.x = staged_row(ring, row, 0, 0);
  job.below = staged_row(ring, row + 1, 0, 0);
  job.first = wind_row(ring, 0, 0);
  job.second = wind_row(ring, 1, 0);
  job.position_span = row_span_;
  job.span = row_span_;
  for (int k = 0; k < 3; ++k) job.direction[k] = wind_direction_[k];
  job.cells = cols_ - 1;
  job.strength = wind_strength_;
  wind_row_forces(job);  // column cols - 1 has no cell and is never written: stays 0
  for (int k = 0; k < 3; ++k) {
    add_cell_winds(accumulator(ring, row, k), accumulator(ring, row + 1, k), wind_row(ring, 0, k),
                   wind_row(ring, 1, k), cols_);
  }
  if (timed) {
    pass.wind_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

template <class Real>
Real ForcePipeline<Real>::finish_row(Real* ring, std::size_t row, Real* out, std::size_t span) {
  const std::size_t cols = cols_;
  const Real* __restrict inverse_mass = inverse_mass_ + row * cols;
  Real probe = 0;
  for (int k = 0; k < 3; ++k) {
    Real* __restrict same = accumulator(ring, row, k, kSameColumn);
    Real* __restrict next = accumulator(ring, row, k, kNextColumn);
    Real* __restrict further = accumulator(ring, row, k, kFurtherColumn);
    Real* __restrict out_k = out + k * span;
    const Real g = gravity_[k];
#pragma omp simd reduction(+ : probe)
    for (std::size_t c = 0; c < cols; ++c) {
      const Real force = same[c] + next[c] + further[c];
      const Real value = inverse_mass[c] > Real(0) ? force * inverse_mass[c] + g : Real(0);
      out_k[c] = value;
      same[c] = next[c] = further[c] = 0;  // ready for row + 3
      probe += value * Real(0);            // NaN exactly when value is not finite
    }
  }
  return probe;
}

template <class Real>
void ForcePipeline<Real>::clear_row(Real* ring, std::size_t row) {
  for (int shift = 0; shift < static_cast<int>(kAccumulatorShifts); ++shift) {
    for (int k = 0; k < 3; ++k) std::fill_n(accumulator(ring, row, k, shift), cols_, Real(0));
  }
}

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
  for (std::size_t row = first; row < end; ++row) {
    // Rows r .. r + 2 staged before row r is run; row r + 3 reuses row r's slot.
    for (; staged < std::min(row + 3, rows_); ++staged) stage_row(thread, own, state, staged);
    add_springs(own, row, pass);
    add_wind(own, row, pass);
    if (row < begin) {
      clear_row(own, row);
    } else if (col_pitch_ == 1) {
      probe += finish_row(own, row, a + row * cols_, stride_);
    } else {
      Real* finished = thread_row(thread, turned_from());
      probe += finish_row(own, row, finished, row_span_);
      scatter_row(finished, a, row);
    }
  }
  // Forces already added to the rows after the block belong to the next thread's rows.
  for (std::size_t row = end; row < std::min(end + 2, rows_); ++row) clear_row(own, row);
  return probe;
}

// Moves each block boundary a row toward the thread that finished first, so a slower core
// (or the halo prelude that only later blocks run) does not leave the other one waiting at
// the barrier. Results do not depend on the boundaries: every block is exact.
template <class Real>
void ForcePipeline<Real>::balance_split() {
  constexpr double kTolerance = 1.02;
  for (std::size_t b = 1; b + 1 < split_.size(); ++b) {
    const double upper = busy_[b - 1], lower = busy_[b];
    if (upper > kTolerance * lower && split_[b] > split_[b - 1] + 1) {
      --split_[b];
    } else if (lower > kTolerance * upper && split_[b] + 1 < split_[b + 1]) {
      ++split_[b];
    }
  }
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

template class ForcePipeline<float>;
template class ForcePipeline<double>;

}  // namespace clothlab::detail
