// The wind stage of ForcePipeline (force_pipeline.hpp): the wind on the cells starting in a
// row (wind_kernel.hpp), its two triangles' shares added to the accumulators of their
// corners' rows. Rows the interior kernel runs have their cells done by the spring stage.
#include <chrono>

#include "force_pipeline.hpp"
#include "shifted_add_kernel.hpp"
#include "wind_kernel.hpp"

namespace clothlab::detail {

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

template void ForcePipeline<float>::add_wind(float*, std::size_t, Pass&);
template void ForcePipeline<double>::add_wind(double*, std::size_t, Pass&);

}  // namespace clothlab::detail
