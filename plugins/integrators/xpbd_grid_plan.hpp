// What xpbd's grid sweep (xpbd_grid_sweep.hpp) works with, built once per prepare: the grid's
// layout, the substep's phases, the multipliers, the common inverse mass and the threads'
// progress. One type for every SIMD target's copy of the sweep.
#pragma once

#include <clothlab/plugin.h>

#include <algorithm>
#include <atomic>
#include <clothlab/sdk/extensions.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "xpbd_bands.hpp"
#include "xpbd_color_row.hpp"
#include "xpbd_grid.hpp"
#include "xpbd_uniform_mass.hpp"
#include "xpbd_wavefront.hpp"

namespace clothlab::builtin {

// The substep's external accelerations where the sweep computes them itself, a few rows ahead
// of its predict pass (clothlab.external-forces/2), instead of a pass of their own before it.
template <class Real>
struct ExternalAhead {
  const sdk::ExternalForces<Real>* forces = nullptr;  // nullptr: `a` is filled before the sweep
  Real* a = nullptr;                                  // the substep's external acceleration
  double t = 0;                                       // the substep's start
};

// A colour's springs that start in one grid row, as the sweep's row jobs take them: whether
// any do, and the positions of those with an end of another inverse mass
// (UniformInverseMass::varied_positions).
struct RowSprings {
  bool starts = false;
  uint32_t varied_begin = 0, varied_end = 0;
};

template <class Real>
struct GridPlan {
  // Grid rows per call of the external accelerations ahead of the predict: each call also
  // recomputes the cells of the row above its first.
  static constexpr uint32_t kExternalRows = 16;

  // Allocates all a substep needs on up to `threads` threads.
  void prepare(GridLayout grid, int iteration_count, uint32_t tether_slots,
               const Real* inverse_mass, uint32_t particle_count, int threads) {
    layout = std::move(grid);
    iterations = iteration_count;
    // n multipliers per colour, kept only when a substep runs more than one iteration.
    lambda.assign(iterations > 1 ? layout.colors.size() * particle_count : 0, 0);
    phases = wavefront_phases(layout, iterations, tether_slots);
    color_rows.assign(phases.size(), ColorRow<Real>{});
    // A thread publishes its progress every few rows' worth of ~2000 columns: each handoff
    // can cost a context switch on a loaded machine, one per narrow row would dominate.
    publish_every = std::max<uint32_t>(1, 2048 / layout.cols);
    uniform.find(inverse_mass, layout.rows, layout.cols);
    row_springs.assign(layout.colors.size() * layout.rows, RowSprings{});
    for (std::size_t color = 0; color < layout.colors.size(); ++color)
      for (uint32_t row = 0; row < layout.rows; ++row) {
        if (!layout.colors[color].starts_in_row(row)) continue;
        const auto [begin, end] = uniform.varied_positions(layout.colors[color], row);
        row_springs[color * layout.rows + row] = {true, static_cast<uint32_t>(begin),
                                                  static_cast<uint32_t>(end)};
      }
    progress = std::make_unique<Progress[]>(static_cast<std::size_t>(threads));
    seam_units = std::make_unique<SeamUnits[]>(phases.size());
  }

  // Whether the sweep may compute the external accelerations ahead of its predict: a row's
  // reads x on the rows beside it, which the velocity pass changes at its lag (0: at once).
  bool computes_external_ahead() const { return phases.back().lag > 0; }

  GridLayout layout;
  int iterations = 1;
  std::vector<Real> lambda;  // per colour n multipliers, from the row's first particle on
  std::vector<Phase> phases;
  // Per phase, a projection's row job but for the row (the sweep fills it per substep).
  std::vector<ColorRow<Real>> color_rows;
  UniformInverseMass uniform;
  // Per colour and grid row, found once: the row jobs' lookup instead of a division and the
  // two rows' spans per call.
  std::vector<RowSprings> row_springs;
  uint32_t publish_every = 1;            // wavefront times between a thread's progress stores
  std::unique_ptr<Progress[]> progress;  // one per thread
  std::unique_ptr<RowClaims> claims = std::make_unique<RowClaims>();  // the two bands' rows
  // Per phase, the seam's two units (the rows below and above the boundary).
  std::unique_ptr<SeamUnits[]> seam_units;
  ExternalAhead<Real> external;  // set per substep
  // The first failed status of the external accelerations' calls in the substep.
  std::atomic<int32_t> external_status{CLOTHLAB_OK};
};

}  // namespace clothlab::builtin
