// Row layout of the force pipeline's per-thread scratch (see force_pipeline.hpp): which rows of a
// thread's region hold what. Rows are row_span elements long; the accessors of ForcePipeline
// turn these indices into addresses.
#pragma once

#include <cstddef>

namespace clothlab::detail::scratch {

// Zeros left of column 0 in every scratch row, so shifted reads need no branch; as much
// again after the last column for the full-width edge blocks of the interior kernel.
inline constexpr std::size_t kMargin = 16;

// A ring, the scratch of one force pass: accumulators (3 ring slots x 3 shifts x 3
// components), force row, wind rows, staged rows (3 ring slots x (x, v) x 3 components).
inline constexpr std::size_t kAccumulatorShifts = 3;
inline constexpr std::size_t kForceRowFrom = 3 * kAccumulatorShifts * 3;
inline constexpr std::size_t kWindRowsFrom = kForceRowFrom + 3;
inline constexpr std::size_t kStagedRowsFrom = kWindRowsFrom + 6;
inline constexpr std::size_t kRowsPerRing = kStagedRowsFrom + 18;

// A thread's region holds a ring per stage of the fused step (rkn_sweep.cpp), then: an
// acceleration window per stage, the halo rows (x and v rows of other threads' blocks, copied
// before anything is written), two update rows, then for a turned grid contiguous copies: of an
// x and a v row (6 rows), of a combination's base and terms (1 + max_terms rows).
constexpr std::size_t window_rows(std::size_t stages) { return 2 * stages; }  // of each window
constexpr std::size_t halo_rows(std::size_t stages) { return 4 * stages; }
constexpr std::size_t windows_from(std::size_t stages) { return stages * kRowsPerRing; }
constexpr std::size_t halo_from(std::size_t stages) {
  return windows_from(stages) + stages * window_rows(stages) * 3;
}
constexpr std::size_t update_from(std::size_t stages) {
  return halo_from(stages) + halo_rows(stages) * 6;
}
constexpr std::size_t turned_from(std::size_t stages) { return update_from(stages) + 2; }
constexpr std::size_t thread_rows(std::size_t stages, std::size_t max_terms) {
  return turned_from(stages) + 7 + max_terms;
}

// A thread's scratch for the external pass (external_pass.cpp): cell shares of two cell
// rows (2 triangles x 3 components each), rows of zeros standing for the cells beyond the
// grid, and for a turned grid contiguous copies of two position rows, two velocity rows (for
// the air) and the finished accelerations.
inline constexpr std::size_t kCellRowsFrom = 0;
inline constexpr std::size_t kZeroCellRowsFrom = kCellRowsFrom + 12;
inline constexpr std::size_t kExternalPositionsFrom = kZeroCellRowsFrom + 6;
inline constexpr std::size_t kExternalVelocitiesFrom = kExternalPositionsFrom + 6;
inline constexpr std::size_t kExternalFinishedFrom = kExternalVelocitiesFrom + 6;
inline constexpr std::size_t kExternalRows = kExternalFinishedFrom + 3;

// Between the threads' scratch regions.
inline constexpr std::size_t kGapBytes = 65536;

}  // namespace clothlab::detail::scratch
