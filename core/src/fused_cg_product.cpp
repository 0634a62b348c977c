// The fused CG kernel of SpringJacobian (spring_jacobian.hpp): the definite product of
// clothlab.cg-step/1 for float with SIMD lanes and all six stencils. linearise_definite stores each
// spring's inverse length once per solve; definite_rows sweeps a thread's rows once per product
// (definite_row_kernel.hpp): q = u + D u, the rows' shares of <u, q> and, with a direction, CG's
// solution and direction updates, all in the one sweep.
#include <algorithm>
#include <type_traits>

#include "simd_namespace.hpp"
#include "spring_jacobian.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
void SpringJacobian<Real>::linearise_definite(const Real* x, const Real* v, double c_x,
                                              double c_v) const {
  linearised_ = {x, v, c_x, c_v};
  if (spring_list_) {
    list_linearise(x);
    return;
  }
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    if (!definite_kernel_) return;
    const auto rows = static_cast<std::ptrdiff_t>(rows_);
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel_)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      const auto row = static_cast<std::size_t>(r);
      for (std::size_t s = 0; s < stencils_.size(); ++s) {
        const StencilSprings& stencil = stencils_[s];
        DefiniteInverseLengthRow job{};
        job.x = x + row * cols_;
        job.x_partner =
            job.x + stencil.row_step * cols_ + static_cast<std::ptrdiff_t>(stencil.col_step);
        job.inverse_length = inverse_length_plane(s) + row * cols_;
        job.stride = stride_, job.cols = cols_;
        const bool spring_row = row < stencil.extent.row_end;
        job.col_begin = spring_row ? stencil.extent.col_begin : 0;
        job.col_end = spring_row ? stencil.extent.col_end : 0;  // no springs: zeros
        definite_inverse_length_row(job);
      }
    }
  }
#endif
}

// With a direction: the thread first updates its block's first and last two rows, which its
// neighbours' sweeps read, then (after a barrier) each interior row as the sweep reaches it: in
// the sweep of the row two above, block by block (the (2,0) springs read it there first), so
// every row is updated once and read only updated.
template <class Real>
void SpringJacobian<Real>::definite_rows(Real* u, Real* out, std::size_t begin, std::size_t end,
                                         Real* scratch, const Direction* direction) const {
#if defined(CLOTHLAB_FLOAT_LANES)
  if constexpr (std::is_same_v<Real, float>) {
    const std::size_t head_end = std::min(begin + 2, end);
    const std::size_t tail_begin = std::max(end >= 2 ? end - 2 : 0, head_end);
    DefiniteDirection update{};
    const auto point_update_at = [&](std::size_t row) {
      const std::size_t base = row * cols_;
      update.z = direction->z + base, update.p = u + base;
      update.solution = direction->solution + base, update.inverse_mass = inverse_mass_ + base;
    };
    const auto update_rows = [&](std::size_t first, std::size_t last) {
      for (std::size_t row = first; row < last; ++row) {
        point_update_at(row);
        definite_direction_row(update, cols_);
      }
    };
    if (direction != nullptr) {  // the same on every thread of the team
      update.alpha = static_cast<float>(direction->alpha);
      update.beta = static_cast<float>(direction->beta);
      update.stride = stride_;
      update_rows(begin, head_end);
      update_rows(tail_begin, end);
#pragma omp barrier
    }
    std::size_t updated = head_end;  // interior rows [head_end, updated) are done
    DefiniteRow job{};
    job.stride = stride_, job.span = span_, job.cols = cols_;
    for (std::size_t k = 0; k < 2; ++k) job.ends_below[k] = scratch + k * 3 * span_;
    const bool damped = damping_ && linearised_.v != nullptr;
    job.c_x = static_cast<float>(linearised_.c_x);
    for (std::size_t s = 0; s < stencils_.size(); ++s) {
      const StencilSprings& stencil = stencils_[s];
      job.ks[s] = stencil.ks, job.ks_rest[s] = stencil.ks * stencil.rest;
      job.along_scale[s] = job.c_x * stencil.ks;
      if (damped) job.along_scale[s] += static_cast<float>(linearised_.c_v) * stencil.kd;
    }
    for (std::size_t row = begin >= 2 ? begin - 2 : 0; row < end; ++row) {
      job.direction_below = nullptr;
      if (direction != nullptr) {
        if (updated < std::min(row + 2, tail_begin)) {
          update_rows(updated, std::min(row + 2, tail_begin));
          updated = std::min(row + 2, tail_begin);
        }
        if (updated == row + 2 && updated < tail_begin) {  // the sweep updates row + 2
          point_update_at(row + 2);
          job.direction_below = &update;
          updated = row + 3;
        }
      }
      for (std::size_t dr = 0; dr < 3; ++dr) {
        const std::size_t base = std::min(row + dr, rows_ - 1) * cols_;
        job.x[dr] = linearised_.x + base, job.u[dr] = u + base;
        job.inverse_mass[dr] = inverse_mass_ + base, job.out[dr] = out + base;
        job.write[dr] = row + dr >= begin && row + dr < end;
        job.first[dr] = dr == 2 || row == 0;
      }
      for (std::size_t s = 0; s < stencils_.size(); ++s)
        job.inverse_length[s] = inverse_length_plane(s) + row * cols_;
      job.mass = mass_.data() + row * cols_;
      job.rows_below[0] = row + 1 < rows_;
      job.rows_below[1] = row + 2 < rows_;
      const double dot = definite_row(job);
      definite_row_shifted_ends(job);
      if (row >= begin) row_dots_[row] = dot;
    }
    return;
  }
#endif
  (void)u, (void)out, (void)begin, (void)end, (void)scratch, (void)direction;
}

template void SpringJacobian<float>::linearise_definite(const float*, const float*, double,
                                                        double) const;
template void SpringJacobian<double>::linearise_definite(const double*, const double*, double,
                                                         double) const;
template void SpringJacobian<float>::definite_rows(float*, float*, std::size_t, std::size_t, float*,
                                                   const Direction*) const;
template void SpringJacobian<double>::definite_rows(double*, double*, std::size_t, std::size_t,
                                                    double*, const Direction*) const;

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
