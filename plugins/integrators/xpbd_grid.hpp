// The regular grid behind a topology, when the host says there is one: XPBD's fast path.
//
// The topology extension publishes springs as arrays and colours as index lists, which
// any mesh can fill. The grid extension (clothlab.grid/1) adds that the cloth is a grid of
// rows x cols particles (index row * cols + col) and that each spring colour is one stencil
// (a fixed step from (row, col) to a partner) at one parity, with one rest length, ks and kd.
// That lets XPBD project a colour one grid row at a time with contiguous vector loads,
// instead of gathering both ends of every spring through its indices. The colours and their
// order stay the topology's, so the fast path runs the same Gauss-Seidel as the general one.
#pragma once

#include <clothlab/sdk.hpp>
#include <cstdint>
#include <optional>
#include <vector>

namespace clothlab::builtin {

// One spring colour on the grid: particle (r, c) joins (r + row_step, c + col_step) for the
// starts in rows [0, row_end), columns [col_begin, col_end) whose (along / step) % 2 is
// `parity`, where `along` runs in the stencil's step direction (the column for in-row
// stencils, the row otherwise).
struct GridColor {
  uint32_t row_step = 0;
  int32_t col_step = 0;
  uint32_t parity = 0;
  uint32_t row_end = 0;
  uint32_t col_begin = 0;
  uint32_t col_end = 0;
  double rest = 0, ks = 0, kd = 0;

  bool in_row() const { return row_step == 0; }
  // Whether springs start in row r (in-row stencils alternate by column instead).
  bool starts_in_row(uint32_t r) const {
    return r < row_end && (in_row() || (r / row_step) % 2 == parity);
  }
};

struct GridLayout {
  uint32_t rows = 0, cols = 0;
  std::vector<GridColor> colors;  // the topology's colours, in its order
};

// The topology's colours laid on the host's grid, or nothing: no grid, colours that are no
// stencils, or a colour without springs (its family has ks = kd = 0), which leaves no law
// for the row kernels to project its stencil with.
inline std::optional<GridLayout> grid_layout(const std::optional<sdk::Grid>& grid,
                                             const sdk::Topology& topology) {
  const uint32_t colors = topology.spring_color_count();
  if (!grid || colors == 0 || grid->spring_colors().size() != colors) return std::nullopt;
  GridLayout layout{grid->rows(), grid->cols(), {}};
  for (uint32_t c = 0; c < colors; ++c) {
    const std::span<const uint32_t> members = topology.spring_color(c);
    if (members.empty()) return std::nullopt;
    const clothlab_grid_color& stencil = grid->spring_colors()[c];
    const uint32_t k = members[0];  // the colour's law: one for all its springs
    layout.colors.push_back({stencil.row_step, stencil.col_step, stencil.parity, stencil.row_end,
                             stencil.col_begin, stencil.col_end, topology.rest_length()[k],
                             topology.ks()[k], topology.kd()[k]});
  }
  return layout;
}

}  // namespace clothlab::builtin
