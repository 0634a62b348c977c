// The wind stage of ForcePipeline (force_pipeline.hpp): the wind (wind_kernel.hpp) and the air
// (air_kernel.hpp) on the cells starting in a row, its two triangles' shares added to the
// accumulators of their corners' rows. Rows the interior kernel runs (never with air) have
// their cells done by the spring stage.
#include <algorithm>
#include <chrono>

#include "force_pipeline.hpp"
#include "shifted_add_kernel.hpp"
#include "simd_namespace.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

template <class Real>
void ForcePipeline<Real>::add_wind(Real* ring, std::size_t row, Pass& pass) {
  if (!cell_forces_ || row + 1 >= rows_) return;  // the last row starts no cell
  if (interior_row(row)) return;                  // its cells went with its springs
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
  if (wind_) {
    wind_row_forces(job);  // column cols - 1 has no cell and is never written: stays 0
  } else {
    for (int triangle = 0; triangle < 2; ++triangle)
      for (int k = 0; k < 3; ++k) std::fill_n(wind_row(ring, triangle, k), job.cells, Real(0));
  }
  if (air_) {
    const bool moving = pass.damped;  // the velocities are staged
    add_air(job.x, job.below, moving ? staged_row(ring, row, 1, 0) : nullptr,
            moving ? staged_row(ring, row + 1, 1, 0) : nullptr, row_span_, job.first, job.second,
            row_span_);
  }
  for (int k = 0; k < 3; ++k) {
    add_cell_winds(accumulator(ring, row, k), accumulator(ring, row + 1, k), wind_row(ring, 0, k),
                   wind_row(ring, 1, k), cols_);
  }
  if (timed) {
    pass.wind_seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
}

template void ForcePipeline<float>::add_wind(float*, std::size_t, Pass&);
template void ForcePipeline<double>::add_wind(double*, std::size_t, Pass&);

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE
