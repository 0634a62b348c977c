// The spring stage of ForcePipeline (force_pipeline.hpp): the forces of the springs starting
// in a row onto the accumulators of rows r .. r + 2. Per stencil through spring_kernel.hpp,
// or, for float with SIMD lanes (float_lanes.hpp), all six stencils and two rows below, all of
// them and the row's cells in one sweep of the interior kernel (interior_row_kernel.hpp).
#include <algorithm>
#include <type_traits>

#include "force_pipeline.hpp"
#include "interior_row_kernel.hpp"
#include "shifted_add_kernel.hpp"
#include "simd_namespace.hpp"
#include "spring_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
void ForcePipeline<Real>::add_springs(Real* ring, std::size_t row, const Pass& pass,
                                      const Real* const* next) {
  if (interior_row(row)) {
    add_interior_springs(ring, row, pass, next);
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
void ForcePipeline<Real>::add_interior_springs(Real* ring, std::size_t row, const Pass& pass,
                                               const Real* const* next) {
#if defined(CLOTHLAB_FLOAT_LANES)
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
    if (next != nullptr) {
      job.next_x = next[0];
      job.next_v = next[1];
      job.next_stride = stride_;
    }
    for (std::size_t s = 0; s < 6; ++s) {
      const SpringStage& stage = stages_[s];
      const bool stage_damped = stage.damped && pass.damped;
      // Undamped ones add 0.
      float law[3];
      spring_law(stage.rest, stage.ks, stage_damped ? stage.kd : 0.0f, kLanesInverseSqrtScale, law);
      for (int t = 0; t < 3; ++t) job.law[s][t] = loop_constant(law[t]);
      damped = damped || stage_damped;
    }
    float pressure[3];
    wind_pressure(wind_direction_, wind_strength_, kLanesInverseSqrtScale, pressure);
    for (int k = 0; k < 3; ++k) job.wind_pressure[k] = broadcast(pressure[k]);
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
  (void)ring, (void)row, (void)pass,
      (void)next;  // only float with SIMD lanes has the interior kernel
}

template void ForcePipeline<float>::add_springs(float*, std::size_t, const Pass&,
                                                const float* const*);
template void ForcePipeline<double>::add_springs(double*, std::size_t, const Pass&,
                                                 const double* const*);

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
