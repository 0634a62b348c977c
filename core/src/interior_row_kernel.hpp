// All six Provot stencils of one interior grid row (a row every stencil starts in), and
// the wind on the cells below it, in two sweeps over its columns, a block of SIMD lanes
// (float_lanes.hpp) at a time: the cell's springs (partners the cell's corners) with the cell's
// wind, then the three others. Two sweeps, each with half the springs, keep each one's pointers
// and values in registers (AVX2 has 16 of each); the own ends' sums go to memory in between.
//
// Per column block the forces on the row's own particles are summed in registers over the
// sweep's springs; only the partners' ends go to memory. A cell's corners are partners of the
// (0,1), (1,0), (1,1) springs, so its wind shares ride on their loads and stores. Each partner end
// whose column is shifted (+1, -1, +2) goes to an accumulator of its own for that shift, so the
// read-modify-writes of one block never overlap each other or the next block's (overlapping ones
// would stall store forwarding). finish_row sums the shifted accumulators. The sweeps of row r are
// the first to write three of them (rows r+1's shifted ones, row r+2's aligned one): they store
// there without reading, so they need no clearing in between (recycle_row, force_pipeline.hpp).
//
// Row r + 3 reuses row r's staged slot. Where it is a plain copy of the state, the far sweep
// stages it there block by block once it has read the block's columns of row r: the copy's
// loads then overlap the sweep's arithmetic instead of running as a pass of their own.
#pragma once

#include <cstddef>

#include "inverse_sqrt.hpp"
#include "simd_namespace.hpp"
#include "spring_kernel.hpp"
#include "wind_kernel.hpp"

#if defined(CLOTHLAB_FLOAT_LANES)

namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE {

// Stencils in kProvotStencils order: (0,1), (1,0), (1,1), (1,-1), (0,2), (2,0).
struct InteriorRow {
  float* x[3];        // positions of rows r, r+1, r+2; row r's slot takes row r+3's (next_x)
  float* v[3];        // velocities likewise; read only when damped
  float* aligned[3];  // accumulators of rows r, r+1, r+2 for ends at the same column
  float* plus1[2];    // rows r, r+1: ends one column to the right
  float* minus1;      // row r+1: ends one column to the left
  float* plus2;       // row r: ends two columns to the right
  std::size_t span;   // between the components of every row above, as in SpringRow
  std::size_t cols;
  LoopConstant law[6][3];   // spring_law's; read as memory operands (float_lanes.hpp)
  Floats wind_pressure[3];  // wind_pressure's; used only with wind
  // Row r+3 of the state (components next_stride apart) for the far sweep to stage into x[0]
  // and v[0]; next_x null: staged elsewhere; next_v null: no velocities.
  const float* next_x;
  const float* next_v;
  std::size_t next_stride;
};

// The springs of one sweep: the cell's (stencils 0-2, and the wind when Wind) or the others (3-5).
enum class InteriorSweep { kCell, kFar };

// Edge blocks (the first, and those reaching the last two columns) mask each spring and
// cell to its columns; their loads and stores may reach into the zero margins around a
// row, where masked lanes add exactly 0.
template <InteriorSweep Sweep, bool Damped, bool Wind, bool Staged, bool Edge>
[[gnu::always_inline]] inline void interior_row_block(const InteriorRow& row, std::size_t c) {
  using Vec3 = Floats[3];
  const std::size_t span = row.span;
  const auto load = [&](const float* p, std::ptrdiff_t shift, Vec3& out) {
    for (std::size_t k = 0; k < 3; ++k) out[k] = load_floats(p + c + k * span + shift);
  };
  const auto mask = [](Vec3& value, LaneMask valid) {
    if constexpr (Edge) {
      for (std::size_t k = 0; k < 3; ++k) value[k] = keep(valid, value[k]);
    }
  };
  const std::size_t cols = row.cols;
  Vec3 own;
  load(row.aligned[0], 0, own);  // what the rows above (and the cell sweep) added to the own ends
  // The spring of stencil s to `partner` (row r + dr, column c + dc): f = scale d on the own end,
  // -f to the partner's accumulator `to`, with the partner's wind share `wind` if given; `first`:
  // this sweep is the first to write `to`, so -f (and the share) is stored without reading it.
  const auto spring = [&](int s, const Vec3& partner, int dr, std::ptrdiff_t dc, LaneMask valid,
                          float* to, const Vec3* wind, bool first) {
    Vec3 d, dv = {};
    // The own end read again per spring rather than held: too few registers for all.
    for (std::size_t k = 0; k < 3; ++k) d[k] = partner[k] - load_floats(row.x[0] + c + k * span);
    if constexpr (Damped) {
      load(row.v[dr], dc, dv);
      for (std::size_t k = 0; k < 3; ++k) dv[k] -= load_floats(row.v[0] + c + k * span);
    }
    const Floats law[3] = {lanes_of(row.law[s][0]), lanes_of(row.law[s][1]),
                           lanes_of(row.law[s][2])};
    Floats scale = spring_force_scale<Damped>(d[0], d[1], d[2], dv[0], dv[1], dv[2], law);
    if constexpr (Edge) {  // both factors 0 outside: 0 d is 0 even where scale is not finite
      scale = keep(valid, scale);
      mask(d, valid);
    }
    for (std::size_t k = 0; k < 3; ++k) {
      own[k] = fused_multiply_add(scale, d[k], own[k]);
      float* q = to + c + k * span + dc;
      Floats sum = first ? zero_floats() : load_floats(q);
      if (wind != nullptr) sum = first ? (*wind)[k] : sum + (*wind)[k];
      store_floats(q, fused_negated_multiply_add(scale, d[k], sum));
    }
  };
  if constexpr (Sweep == InteriorSweep::kCell) {
    // The cell's corners other than x are partners of the first three stencils.
    Vec3 x, right, below, below_right;
    load(row.x[0], 0, x);
    load(row.x[0], 1, right);
    load(row.x[1], 0, below);
    load(row.x[1], 1, below_right);
    // Wind first: its shares join the partner ends of the first three springs, so only one
    // partner sum is alive at a time (fewer registers spilled).
    Vec3 both = {}, second = {};  // shares of corners b and c' (both triangles), d (second)
    if constexpr (Wind) {
      Vec3 first;
      cell_wind_shares(x, right, below, below_right, row.wind_pressure, first, second);
      const LaneMask cells = columns_in(c, 0, cols - 1);
      mask(first, cells);
      mask(second, cells);
      for (std::size_t k = 0; k < 3; ++k) {
        own[k] += first[k];
        both[k] = first[k] + second[k];
      }
    }
    const Vec3* wind_both = Wind ? &both : nullptr;
    spring(0, right, 0, 1, columns_in(c, 0, cols - 1), row.plus1[0], wind_both, false);
    spring(1, below, 1, 0, columns_in(c, 0, cols), row.aligned[1], wind_both, false);
    spring(2, below_right, 1, 1, columns_in(c, 0, cols - 1), row.plus1[1], Wind ? &second : nullptr,
           true);
  } else {
    Vec3 far;
    load(row.x[1], -1, far);
    spring(3, far, 1, -1, columns_in(c, 1, cols), row.minus1, nullptr, true);
    load(row.x[0], 2, far);
    spring(4, far, 0, 2, columns_in(c, 0, cols - 2), row.plus2, nullptr, false);
    load(row.x[2], 0, far);
    spring(5, far, 2, 0, columns_in(c, 0, cols), row.aligned[2], nullptr, true);
  }
  for (std::size_t k = 0; k < 3; ++k) store_floats(row.aligned[0] + c + k * span, own[k]);
  if constexpr (Staged) {  // the sweep is done with these columns of row r
    const auto stage = [&](const float* from, float* to) {
      for (std::size_t k = 0; k < 3; ++k) {
        const float* p = from + c + k * row.next_stride;
        // Masked loads stay within the state; the margin past the last column gets zeros.
        store_floats(to + c + k * span,
                     Edge ? load_floats(columns_in(c, 0, cols), p) : load_floats(p));
      }
    };
    stage(row.next_x, row.x[0]);
    if (row.next_v != nullptr) stage(row.next_v, row.v[0]);
  }
}

template <InteriorSweep Sweep, bool Damped, bool Wind, bool Staged>
inline void interior_row_sweep(const InteriorRow& job) {
  // A copy of its own: the kernel's float stores could alias the caller's, whose pointers the
  // loop would then load again after every store.
  const InteriorRow row = job;
  const std::size_t cols = row.cols;
  std::size_t c = 0;
  interior_row_block<Sweep, Damped, Wind, Staged, true>(row, c);
  // Blocks clear of both edges: every lane of every stencil is a spring.
  for (c = kLanes; c + kLanes + 2 <= cols; c += kLanes)
    interior_row_block<Sweep, Damped, Wind, Staged, false>(row, c);
  // The (1,-1) springs store their partners' ends a column to the left, so that sweep runs
  // until it has stored column cols - 1 too (a block of masked lanes where cols fills its last).
  const std::size_t end = Sweep == InteriorSweep::kFar ? cols + 1 : cols;
  for (; c < end; c += kLanes) interior_row_block<Sweep, Damped, Wind, Staged, true>(row, c);
}

template <bool Damped, bool Wind>
inline void interior_row_forces(const InteriorRow& row) {
  interior_row_sweep<InteriorSweep::kCell, Damped, Wind, false>(row);
  if (row.next_x != nullptr) {
    interior_row_sweep<InteriorSweep::kFar, Damped, false, true>(row);
  } else {
    interior_row_sweep<InteriorSweep::kFar, Damped, false, false>(row);
  }
}

}  // namespace clothlab::detail::inline CLOTHLAB_SIMD_NAMESPACE

#endif
