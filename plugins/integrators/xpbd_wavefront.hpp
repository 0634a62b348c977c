// The order of an XPBD substep on the grid: a wavefront over the rows instead of one pass
// over the cloth per colour.
//
// The phases (predict, each iteration's colours, tethers, velocity) visit row T - lag(phase)
// at wavefront time T, the lags growing by each colour's row reach (0, 1 or 2 rows), so
// every spring sees its ends exactly as the colour-by-colour order leaves them while the
// rows in flight stay in cache. Going up from the last row instead, a phase visits start row
// rows - 1 - T + lag(phase) - its row reach (`upward_offset`).
#pragma once

#include <cstdint>
#include <vector>

#include "xpbd_grid.hpp"

namespace clothlab::builtin {

// One stage of a substep on the grid, applied row by row.
struct Phase {
  enum class Kind : uint8_t { predict, project, tether, velocity };
  Kind kind;
  uint32_t color;          // project: the grid layout's colour
  uint32_t iteration;      // project
  uint32_t lag;            // wavefront times before its row 0, going down
  uint32_t upward_offset;  // lag - the phase's row reach: going up, the start row's offset
  uint64_t cost;           // work units, for splitting the phases between threads
};

// The phases of a substep in Gauss-Seidel order and their lags: a phase may visit a row
// once every earlier phase is done with all rows its springs reach (its row step below),
// and a later phase reaches no row it has yet to visit.
inline std::vector<Phase> wavefront_phases(const GridLayout& grid, int iterations,
                                           uint32_t tether_slots) {
  std::vector<Phase> phases;
  const uint64_t row_of_particles = grid.cols;
  phases.push_back({Phase::Kind::predict, 0, 0, 0, 0, grid.rows * row_of_particles / 3});
  uint32_t lag = 0;
  for (uint32_t iteration = 0; iteration < static_cast<uint32_t>(iterations); ++iteration)
    for (uint32_t c = 0; c < grid.colors.size(); ++c) {
      const GridColor& color = grid.colors[c];
      lag += color.row_step;
      uint64_t rows = 0;
      for (uint32_t r = 0; r < grid.rows; ++r) rows += color.starts_in_row(r);
      phases.push_back({Phase::Kind::project, c, iteration, lag, lag - color.row_step,
                        rows * (color.col_end - color.col_begin)});
    }
  // Tethers move only their own particle: like the velocity phase, a row's may run as soon
  // as the last colour is done with it, going down or up.
  if (tether_slots > 0)
    phases.push_back(
        {Phase::Kind::tether, 0, 0, lag, lag, grid.rows * row_of_particles * tether_slots / 4});
  phases.push_back({Phase::Kind::velocity, 0, 0, lag, lag, grid.rows * row_of_particles / 3});
  return phases;
}

}  // namespace clothlab::builtin
