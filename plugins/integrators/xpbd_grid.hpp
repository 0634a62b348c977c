// The regular grid behind a topology, when there is one: XPBD's fast path.
//
// The topology extension publishes springs as arrays and colours as index lists, which
// any mesh can fill. On the Provot grid of rows x cols particles (index row * cols + col)
// each spring colour is one stencil (a fixed step from (row, col) to a partner) at one
// parity, with one rest length, ks and kd. Recognising that lets XPBD project a colour one
// grid row at a time with contiguous vector loads, instead of gathering both ends of every
// spring through its indices. The colours and their order stay the topology's, so the fast
// path runs the same Gauss-Seidel as the general one.
#pragma once

#include <algorithm>
#include <array>
#include <clothlab/sdk.hpp>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace clothlab::builtin {

// Particle (r, c) joins (r + row_step, c + col_step): structural, shear and flexion.
struct GridStencil {
  uint32_t row_step;
  int32_t col_step;
};
inline constexpr std::array<GridStencil, 6> grid_stencils{
    {{0, 1}, {1, 0}, {1, 1}, {1, -1}, {0, 2}, {2, 0}}};

// One spring colour on the grid: the springs of `stencil` whose start (r, c) has
// (along / step) % 2 == parity, where `along` runs in the stencil's step direction
// (the column for in-row stencils, the row otherwise).
struct GridColor {
  uint32_t stencil = 0;
  uint32_t parity = 0;
  uint32_t row_end = 0;  // starts lie in rows [0, row_end), columns [col_begin, col_end)
  uint32_t col_begin = 0;
  uint32_t col_end = 0;
  double rest = 0, ks = 0, kd = 0;

  const GridStencil& step() const { return grid_stencils[stencil]; }
  bool in_row() const { return step().row_step == 0; }
  // Whether springs start in row r (in-row stencils alternate by column instead).
  bool starts_in_row(uint32_t r) const {
    return r < row_end && (in_row() || (r / step().row_step) % 2 == parity);
  }
  bool starts_at(uint32_t r, uint32_t c) const {
    if (!starts_in_row(r) || c < col_begin || c >= col_end) return false;
    return !in_row() || (c / static_cast<uint32_t>(step().col_step)) % 2 == parity;
  }
};

struct GridLayout {
  uint32_t rows = 0, cols = 0;
  std::vector<GridColor> colors;  // the topology's colours, in its order
};

namespace detail {

inline GridColor grid_color(uint32_t stencil, uint32_t parity, uint32_t rows, uint32_t cols) {
  const GridStencil& s = grid_stencils[stencil];
  GridColor color;
  color.stencil = stencil;
  color.parity = parity;
  color.row_end = rows > s.row_step ? rows - s.row_step : 0;
  if (s.col_step >= 0) {
    const auto step = static_cast<uint32_t>(s.col_step);
    color.col_end = cols > step ? cols - step : 0;
  } else {
    color.col_begin = static_cast<uint32_t>(-s.col_step);
    color.col_end = cols;
  }
  return color;
}

inline uint64_t spring_count(const GridColor& color, uint32_t rows) {
  uint64_t count = 0;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = color.col_begin; c < color.col_end; ++c) count += color.starts_at(r, c);
  return count;
}

// The colour `members` form on a cols-wide grid, or nothing: one stencil, one parity,
// every spring of that set present, one spring law.
inline std::optional<GridColor> match_color(const sdk::Topology& topology,
                                            std::span<const uint32_t> members, uint32_t rows,
                                            uint32_t cols) {
  if (members.empty()) return std::nullopt;
  const uint32_t k0 = members[0];
  const int64_t offset = int64_t{topology.second()[k0]} - topology.first()[k0];
  std::optional<uint32_t> stencil;
  for (uint32_t s = 0; s < grid_stencils.size(); ++s)
    if (int64_t{grid_stencils[s].row_step} * cols + grid_stencils[s].col_step == offset)
      stencil = s;
  if (!stencil) return std::nullopt;
  const uint32_t start = topology.first()[k0];
  const GridStencil& step = grid_stencils[*stencil];
  const uint32_t along = step.row_step == 0 ? start % cols : start / cols;
  const uint32_t stride = step.row_step == 0 ? static_cast<uint32_t>(step.col_step) : step.row_step;
  GridColor color = grid_color(*stencil, (along / stride) % 2, rows, cols);
  color.rest = topology.rest_length()[k0];
  color.ks = topology.ks()[k0];
  color.kd = topology.kd()[k0];
  for (uint32_t k : members) {
    const uint32_t i = topology.first()[k];
    if (int64_t{topology.second()[k]} - i != offset || !color.starts_at(i / cols, i % cols) ||
        topology.rest_length()[k] != color.rest || topology.ks()[k] != color.ks ||
        topology.kd()[k] != color.kd)
      return std::nullopt;
  }
  // The members are distinct springs of the set (a colour shares no particle), so the
  // count tells whether all of the set is there.
  if (spring_count(color, rows) != members.size()) return std::nullopt;
  return color;
}

inline std::optional<GridLayout> match_grid(const sdk::Topology& topology, uint32_t cols) {
  const uint32_t n = topology.particle_count();
  // Below 4 columns the stencils' offsets (1, 2, cols - 1, cols, cols + 1, 2 cols) collide.
  if (cols < 4 || n % cols != 0 || n / cols < 3) return std::nullopt;
  GridLayout layout{n / cols, cols, {}};
  std::array<bool, 2 * grid_stencils.size()> used{};
  for (uint32_t c = 0; c < topology.spring_color_count(); ++c) {
    const std::optional<GridColor> color =
        match_color(topology, topology.spring_color(c), layout.rows, cols);
    if (!color || used[2 * color->stencil + color->parity]) return std::nullopt;
    used[2 * color->stencil + color->parity] = true;
    layout.colors.push_back(*color);
  }
  return layout;
}

}  // namespace detail

// The grid the topology's springs and colours are laid out on, or nothing.
inline std::optional<GridLayout> recognise_grid(const sdk::Topology& topology) {
  if (topology.spring_count() == 0 || topology.spring_color_count() == 0) return std::nullopt;
  uint32_t widest = 0;
  for (uint32_t k = 0; k < topology.spring_count(); ++k)
    widest = std::max(widest, topology.second()[k] - topology.first()[k]);
  // The widest step is cols (structural), cols + 1 (shear) or 2 cols (flexion).
  for (uint32_t cols : {widest, widest - 1, widest % 2 == 0 ? widest / 2 : 0u})
    if (std::optional<GridLayout> layout = detail::match_grid(topology, cols)) return layout;
  return std::nullopt;
}

}  // namespace clothlab::builtin
