#include "grid_topology.hpp"

#include "grid.hpp"

namespace clothlab::detail {
namespace {

uint8_t family_id(SpringFamily Scene::*family) {
  if (family == &Scene::structural) return CLOTHLAB_SPRING_STRUCTURAL;
  if (family == &Scene::shear) return CLOTHLAB_SPRING_SHEAR;
  return CLOTHLAB_SPRING_FLEXION;
}

// Members grouped by their colour, ascending within a colour (CSR).
void group_by_color(const std::vector<uint32_t>& color_of, uint32_t colors,
                    std::vector<uint32_t>& offsets, std::vector<uint32_t>& members) {
  offsets.assign(colors + 1, 0);
  for (uint32_t color : color_of) ++offsets[color + 1];
  for (uint32_t c = 0; c < colors; ++c) offsets[c + 1] += offsets[c];
  members.resize(color_of.size());
  std::vector<uint32_t> next(offsets.begin(), offsets.end() - 1);
  for (uint32_t item = 0; item < color_of.size(); ++item) members[next[color_of[item]]++] = item;
}

}  // namespace

uint32_t spring_color(std::size_t stencil, uint32_t row, uint32_t col) {
  const Stencil& s = kProvotStencils[stencil];
  // Springs of one stencil share a particle only when their starts are one step apart
  // along it: alternate along the step's row (or column, for in-row stencils).
  const uint32_t along = s.row_step == 0 ? col : row;
  const uint32_t step = s.row_step == 0 ? static_cast<uint32_t>(s.col_step) : s.row_step;
  return static_cast<uint32_t>(2 * stencil) + (along / step) % 2;
}

GridTopology::GridTopology(const Scene& scene)
    : rows(scene.rows),
      cols(scene.cols),
      column_spacing(scene.column_spacing()),
      row_spacing(scene.row_spacing()),
      particle_count(scene.rows * scene.cols) {
  const uint32_t n = particle_count;
  std::vector<uint32_t> spring_colors;
  for (std::size_t s = 0; s < kProvotStencils.size(); ++s) {
    const Stencil& stencil = kProvotStencils[s];
    const StencilExtent extent = stencil_extent(stencil, rows, cols);
    for (uint32_t parity = 0; parity < 2; ++parity)  // colours 2 s and 2 s + 1 (spring_color)
      grid_colors.push_back({stencil.row_step, stencil.col_step, parity, extent.row_end,
                             extent.col_begin, extent.col_end});
    const SpringFamily& law = scene.*stencil.family;
    if (law.ks == 0.0 && law.kd == 0.0) continue;
    const double rest = stencil_rest_length(scene, stencil);
    const int64_t offset = stencil_offset(stencil, cols);
    for (uint32_t r = 0; r < extent.row_end; ++r) {
      for (uint32_t c = extent.col_begin; c < extent.col_end; ++c) {
        const uint32_t i = r * cols + c;
        first.push_back(i);
        second.push_back(static_cast<uint32_t>(i + offset));
        rest_length.push_back(rest);
        ks.push_back(law.ks);
        kd.push_back(law.kd);
        family.push_back(family_id(stencil.family));
        spring_colors.push_back(spring_color(s, r, c));
      }
    }
  }

  triangles = grid_triangles(rows, cols);

  // Adjacency: springs are visited in ascending index, so each particle's list ascends.
  adjacency_offsets.assign(n + 1, 0);
  for (std::size_t k = 0; k < first.size(); ++k) {
    ++adjacency_offsets[first[k] + 1];
    ++adjacency_offsets[second[k] + 1];
  }
  for (uint32_t i = 0; i < n; ++i) adjacency_offsets[i + 1] += adjacency_offsets[i];
  adjacent_springs.resize(adjacency_offsets[n]);
  std::vector<uint32_t> next(adjacency_offsets.begin(), adjacency_offsets.end() - 1);
  for (uint32_t k = 0; k < first.size(); ++k) {
    adjacent_springs[next[first[k]]++] = k;
    adjacent_springs[next[second[k]]++] = k;
  }

  group_by_color(spring_colors, kSpringColors, spring_color_offsets, spring_color_members);
  std::vector<uint32_t> particle_colors(n);
  for (uint32_t i = 0; i < n; ++i) particle_colors[i] = particle_color(i / cols, i % cols);
  group_by_color(particle_colors, kParticleColors, particle_color_offsets, particle_color_members);
}

clothlab_topology GridTopology::view() const {
  clothlab_topology out{};
  out.struct_size = sizeof out;
  out.particle_count = particle_count;
  out.spring_count = static_cast<uint32_t>(first.size());
  out.triangle_count = static_cast<uint32_t>(triangles.size() / 3);
  out.first = first.data();
  out.second = second.data();
  out.rest_length = rest_length.data();
  out.ks = ks.data();
  out.kd = kd.data();
  out.family = family.data();
  out.triangles = triangles.data();
  out.adjacency_offsets = adjacency_offsets.data();
  out.adjacent_springs = adjacent_springs.data();
  out.spring_color_count = kSpringColors;
  out.spring_color_offsets = spring_color_offsets.data();
  out.spring_color_members = spring_color_members.data();
  out.particle_color_count = kParticleColors;
  out.particle_color_offsets = particle_color_offsets.data();
  out.particle_color_members = particle_color_members.data();
  return out;
}

clothlab_grid GridTopology::grid_view() const {
  clothlab_grid out{};
  out.struct_size = sizeof out;
  out.rows = rows;
  out.cols = cols;
  out.spring_color_count = static_cast<uint32_t>(grid_colors.size());
  out.column_spacing = column_spacing;
  out.row_spacing = row_spacing;
  out.spring_colors = grid_colors.data();
  return out;
}

}  // namespace clothlab::detail
