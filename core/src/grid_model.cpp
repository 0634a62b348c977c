// The grid builder: the Provot springs of a rows x cols scene as a spring list, with the grid's
// fixed colourings (stencil and parity for springs, (row + 2 col) mod 5 for particles).
#include <algorithm>
#include <clothlab/core/cloth_model.hpp>
#include <stdexcept>
#include <string>

#include "grid.hpp"
#include "grid_colors.hpp"

namespace clothlab {
namespace {

uint8_t family_id(SpringFamily Scene::*family) {
  if (family == &Scene::structural) return CLOTHLAB_SPRING_STRUCTURAL;
  if (family == &Scene::shear) return CLOTHLAB_SPRING_SHEAR;
  return CLOTHLAB_SPRING_FLEXION;
}

}  // namespace

std::shared_ptr<const ClothModel> build_grid_model(const Scene& scene) {
  using namespace detail;
  const uint32_t rows = scene.rows, cols = scene.cols;
  if (rows < 1 || cols < 1) {
    throw std::invalid_argument("scene " + std::to_string(rows) + "x" + std::to_string(cols) +
                                ": allowed rows, cols >= 1");
  }
  const uint32_t n = rows * cols;
  for (uint32_t pinned : scene.pinned) {
    if (pinned >= n) {
      throw std::invalid_argument("scene.pinned = " + std::to_string(pinned) +
                                  ": allowed indices < rows*cols = " + std::to_string(n));
    }
  }
  auto model = std::make_shared<ClothModel>();
  model->particle_count = n;
  model->grid = GridShape{rows, cols};
  model->rest_positions.resize(3 * std::size_t{n});
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      const Vec3 p = initial_position(scene, r, c);
      for (int k = 0; k < 3; ++k) model->rest_positions[3 * (std::size_t{r} * cols + c) + k] = p[k];
    }
  model->masses.assign(n, scene.total_mass / static_cast<double>(n));
  // n / total rather than 1 / mass: the engine's inverse mass, to the bit.
  model->inverse_masses.assign(n, static_cast<double>(n) / scene.total_mass);
  model->triangles = grid_triangles(rows, cols);

  std::vector<uint32_t> spring_colors;
  for (std::size_t s = 0; s < kProvotStencils.size(); ++s) {
    const Stencil& stencil = kProvotStencils[s];
    const SpringFamily& law = scene.*stencil.family;
    if (law.ks == 0.0 && law.kd == 0.0) continue;
    const StencilExtent extent = stencil_extent(stencil, rows, cols);
    const double rest = stencil_rest_length(scene, stencil);
    const int64_t offset = stencil_offset(stencil, cols);
    for (uint32_t r = 0; r < extent.row_end; ++r) {
      for (uint32_t c = extent.col_begin; c < extent.col_end; ++c) {
        const uint32_t i = r * cols + c;
        model->first.push_back(i);
        model->second.push_back(static_cast<uint32_t>(i + offset));
        model->rest_length.push_back(rest);
        model->ks.push_back(law.ks);
        model->kd.push_back(law.kd);
        model->family.push_back(family_id(stencil.family));
        spring_colors.push_back(grid_spring_color(s, r, c));
      }
    }
  }
  build_adjacency(*model);
  apply_pins(*model, scene.pinned);
  model->spring_colors = group_by_color(spring_colors, kGridSpringColors);
  std::vector<uint32_t> particle_colors(n);
  for (uint32_t i = 0; i < n; ++i) particle_colors[i] = grid_particle_color(i / cols, i % cols);
  model->particle_colors = group_by_color(particle_colors, kGridParticleColors);
  return model;
}

namespace detail {

void build_adjacency(ClothModel& model) {
  const uint32_t n = model.particle_count;
  // Springs are visited in ascending index, so each particle's list ascends.
  model.adjacency_offsets.assign(n + 1, 0);
  for (std::size_t k = 0; k < model.first.size(); ++k) {
    ++model.adjacency_offsets[model.first[k] + 1];
    ++model.adjacency_offsets[model.second[k] + 1];
  }
  for (uint32_t i = 0; i < n; ++i) model.adjacency_offsets[i + 1] += model.adjacency_offsets[i];
  model.adjacent_springs.resize(model.adjacency_offsets[n]);
  std::vector<uint32_t> next(model.adjacency_offsets.begin(), model.adjacency_offsets.end() - 1);
  for (uint32_t k = 0; k < model.first.size(); ++k) {
    model.adjacent_springs[next[model.first[k]]++] = k;
    model.adjacent_springs[next[model.second[k]]++] = k;
  }
}

void apply_pins(ClothModel& model, const std::vector<uint32_t>& pinned) {
  model.pinned = pinned;
  std::sort(model.pinned.begin(), model.pinned.end());
  model.pinned.erase(std::unique(model.pinned.begin(), model.pinned.end()), model.pinned.end());
  for (uint32_t index : model.pinned) {
    if (index >= model.particle_count)
      throw std::invalid_argument("scene.pinned = " + std::to_string(index) +
                                  ": allowed indices < the particle count " +
                                  std::to_string(model.particle_count));
    model.inverse_masses[index] = 0.0;
  }
}

}  // namespace detail
}  // namespace clothlab
