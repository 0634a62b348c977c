// The grid cloth's springs, triangles, particle -> spring adjacency and colourings as
// plain arrays (the host side of "clothlab.topology/1"), and its spring colours as stencils
// on the grid ("clothlab.grid/1"), built once from the scene.
#pragma once

#include <clothlab/ext/grid.h>
#include <clothlab/ext/topology.h>

#include <clothlab/core/cloth.hpp>
#include <cstdint>
#include <vector>

namespace clothlab::detail {

struct GridTopology {
  explicit GridTopology(const Scene& scene);

  // Views into the arrays (valid while this object lives).
  clothlab_topology view() const;
  clothlab_grid grid_view() const;

  std::size_t spring_count() const { return first.size(); }

  std::vector<uint32_t> first, second;
  std::vector<double> rest_length, ks, kd;
  std::vector<uint8_t> family;
  std::vector<uint32_t> triangles;
  std::vector<uint32_t> adjacency_offsets, adjacent_springs;
  std::vector<uint32_t> spring_color_offsets, spring_color_members;
  std::vector<uint32_t> particle_color_offsets, particle_color_members;
  std::vector<clothlab_grid_color> grid_colors;  // colour c's stencil and parity
  uint32_t rows = 0, cols = 0;
  double column_spacing = 0, row_spacing = 0;
  uint32_t particle_count = 0;
};

// Colour of the spring of stencil `stencil` starting at (row, col): 6 stencils x 2
// parities; flexion stencils (step 2) alternate every two rows or columns.
uint32_t spring_color(std::size_t stencil, uint32_t row, uint32_t col);
inline constexpr uint32_t kSpringColors = 12;
// (row + 2 col) mod 5: no Provot stencil step (0,1),(1,0),(1,±1),(0,2),(2,0) is 0 mod 5.
inline constexpr uint32_t kParticleColors = 5;
inline uint32_t particle_color(uint32_t row, uint32_t col) { return (row + 2 * col) % 5; }

}  // namespace clothlab::detail
