// The cloth as data (the shape of Jolt's SoftBodySharedSettings): rest positions, masses,
// triangles, springs, pins and colourings, built once by a builder (the grid's, below, or the
// triangle mesh's, triangle_mesh.hpp) and then immutable, shared by everything that reads the
// cloth (engine, energy and stretch, the topology extension, frames).
#pragma once

#include <clothlab/ext/topology.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/coloring.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

namespace clothlab {

// The rows x cols lattice a grid model's particles lie on: particle r * cols + c.
struct GridShape {
  uint32_t rows = 0;
  uint32_t cols = 0;
};

struct ClothModel {
  uint32_t particle_count = 0;
  std::vector<double> rest_positions;  // 3 per particle, particle-major (m)
  std::vector<double> masses;          // kg, one per particle
  std::vector<double> inverse_masses;  // 1 / kg; 0 where pinned
  std::vector<uint32_t> pinned;        // ascending, unique
  // 3 per triangle, counter-clockwise about the side the normal points to: what wind and air
  // act on, what frames draw.
  std::vector<uint32_t> triangles;

  // Springs, one entry each: first[k] < second[k], Hooke ks (N/m) about rest_length (m) plus
  // damping kd (N s/m), family CLOTHLAB_SPRING_*. Families with ks = kd = 0 are left out.
  std::vector<uint32_t> first, second;
  std::vector<double> rest_length, ks, kd;
  std::vector<uint8_t> family;

  // Particle -> spring lists (CSR), ascending: particle i's springs are
  // adjacent_springs[adjacency_offsets[i] .. adjacency_offsets[i + 1]).
  std::vector<uint32_t> adjacency_offsets, adjacent_springs;
  Coloring spring_colors;    // no two springs of a colour share a particle
  Coloring particle_colors;  // no spring joins two particles of a colour

  // Set when the particles lie on a grid with the Provot springs (the engine's fast path).
  std::optional<GridShape> grid;

  std::size_t spring_count() const { return first.size(); }
  std::size_t triangle_count() const { return triangles.size() / 3; }
};

// The rows x cols grid of `scene`: the Provot springs (structural (0,1),(1,0), shear (1,±1),
// flexion (0,2),(2,0)) in stencil order, the cells' triangles (grid_triangles), equal masses,
// the 12 stencil-parity spring colours and the 5 particle colours (row + 2 col) mod 5.
std::shared_ptr<const ClothModel> build_grid_model(const Scene& scene);

namespace detail {
// The parts every builder shares: the adjacency lists from the springs; the masses' inverses
// with the pins applied. Throws std::invalid_argument for a pin out of range.
void build_adjacency(ClothModel& model);
void apply_pins(ClothModel& model, const std::vector<uint32_t>& pinned);
}  // namespace detail

}  // namespace clothlab
