// The grid's fixed colourings: springs by stencil and parity (12), particles by
// (row + 2 col) mod 5; and the spring colours as stencils for "clothlab.grid/1".
#pragma once

#include <clothlab/ext/grid.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "grid.hpp"

namespace clothlab::detail {

// Colour of the spring of stencil `stencil` starting at (row, col): 6 stencils x 2
// parities; flexion stencils (step 2) alternate every two rows or columns.
inline uint32_t grid_spring_color(std::size_t stencil, uint32_t row, uint32_t col) {
  const Stencil& s = kProvotStencils[stencil];
  // Springs of one stencil share a particle only when their starts are one step apart
  // along it: alternate along the step's row (or column, for in-row stencils).
  const uint32_t along = s.row_step == 0 ? col : row;
  const uint32_t step = s.row_step == 0 ? static_cast<uint32_t>(s.col_step) : s.row_step;
  return static_cast<uint32_t>(2 * stencil) + (along / step) % 2;
}
inline constexpr uint32_t kGridSpringColors = 12;
// (row + 2 col) mod 5: no Provot stencil step (0,1),(1,0),(1,±1),(0,2),(2,0) is 0 mod 5.
inline constexpr uint32_t kGridParticleColors = 5;
inline uint32_t grid_particle_color(uint32_t row, uint32_t col) { return (row + 2 * col) % 5; }

// The grid's spring colours as stencil and parity over the rows x cols grid, colour c at c.
inline std::vector<clothlab_grid_color> grid_stencil_colors(uint32_t rows, uint32_t cols) {
  std::vector<clothlab_grid_color> colors;
  for (const Stencil& stencil : kProvotStencils) {
    const StencilExtent extent = stencil_extent(stencil, rows, cols);
    for (uint32_t parity = 0; parity < 2; ++parity)
      colors.push_back({stencil.row_step, stencil.col_step, parity, extent.row_end,
                        extent.col_begin, extent.col_end});
  }
  return colors;
}

}  // namespace clothlab::detail
