// Triangle meshes built in code for the mesh tests and the mesh path's benchmark: a scene's grid
// written as triangles, a disc and an irregular (jittered, randomly split) sheet; and the RK4
// scheme they step with.
#pragma once

#include <clothlab/plugin.h>

#include <clothlab/core/cloth.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

namespace clothlab::testing {

// How each grid cell is split: along the diagonal from (r, c) to (r+1, c+1) ("\"), along the
// other one ("/"), or alternating like a chequerboard.
enum class Diagonals { Falling, Rising, Alternating };

// The grid of `scene` as triangles over the same positions (the engine's layout), each cell two
// counter-clockwise triangles as `diagonals` says.
inline TriangleMesh grid_mesh(const Scene& scene, Diagonals diagonals) {
  TriangleMesh mesh;
  const uint32_t rows = scene.rows, cols = scene.cols;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c)
      for (int k = 0; k < 3; ++k)
        mesh.positions.push_back(scene.origin[k] + c * scene.column_spacing() * scene.col_axis[k] +
                                 r * scene.row_spacing() * scene.row_axis[k]);
  for (uint32_t r = 0; r + 1 < rows; ++r)
    for (uint32_t c = 0; c + 1 < cols; ++c) {
      const uint32_t a = r * cols + c, b = a + 1, below = a + cols, d = below + 1;
      const bool falling = diagonals == Diagonals::Falling ||
                           (diagonals == Diagonals::Alternating && (r + c) % 2 == 0);
      if (falling)
        mesh.triangles.insert(mesh.triangles.end(), {a, b, d, a, d, below});
      else
        mesh.triangles.insert(mesh.triangles.end(), {a, below, b, b, below, d});
    }
  return mesh;
}

// A disc of `rings` rings around a centre, ring k of 6k vertices at radius k * spacing, in the
// xy plane: every inner vertex has about six neighbours, as in a remeshed garment.
inline TriangleMesh disc_mesh(uint32_t rings, double spacing) {
  TriangleMesh mesh;
  mesh.positions = {0.0, 0.0, 0.0};
  uint32_t inner_first = 0, inner_count = 1;
  for (uint32_t k = 1; k <= rings; ++k) {
    const uint32_t outer_first = static_cast<uint32_t>(mesh.positions.size() / 3);
    const uint32_t outer_count = 6 * k;
    for (uint32_t j = 0; j < outer_count; ++j) {
      const double angle = 2 * std::numbers::pi * j / outer_count;
      mesh.positions.insert(mesh.positions.end(),
                            {k * spacing * std::cos(angle), k * spacing * std::sin(angle), 0.0});
    }
    // Zip the two rings by angle: each triangle advances one of them by a vertex.
    const uint32_t triangles = (inner_count > 1 ? inner_count : 0) + outer_count;
    for (uint32_t t = 0, i = 0, j = 0; t < triangles; ++t) {
      const uint32_t inner = inner_first + i % inner_count;
      const uint32_t outer = outer_first + j % outer_count;
      const bool advance_inner =
          inner_count > 1 && i < inner_count &&
          (j == outer_count || uint64_t{i + 1} * outer_count < uint64_t{j + 1} * inner_count);
      if (advance_inner) {
        mesh.triangles.insert(mesh.triangles.end(),
                              {inner, outer, inner_first + (i + 1) % inner_count});
        ++i;
      } else {
        mesh.triangles.insert(mesh.triangles.end(),
                              {inner, outer, outer_first + (j + 1) % outer_count});
        ++j;
      }
    }
    inner_first = outer_first;
    inner_count = outer_count;
  }
  return mesh;
}

// A rows x cols sheet of unit spacing in the xy plane, jittered and split at random
// (irregular_grid_mesh): no rectangles, no straight lines of edges.
inline TriangleMesh irregular_mesh(uint32_t rows, uint32_t cols) {
  Scene layout;
  layout.rows = rows;
  layout.cols = cols;
  layout.width = cols - 1.0;
  layout.height = rows - 1.0;
  return irregular_grid_mesh(layout);
}

// Vertex i of n renumbered as (i * step) mod n (step coprime to n): a numbering that puts a
// triangle's corners far apart.
inline uint32_t renumbered_index(uint32_t i, uint32_t step, uint32_t n) {
  return static_cast<uint32_t>(uint64_t{i} * step % n);
}

// Three values per vertex, vertex i's moved to vertex to[i] (a permutation).
inline std::vector<double> renumbered_values(const std::vector<double>& values,
                                             const std::vector<uint32_t>& to) {
  std::vector<double> out(values.size());
  for (std::size_t i = 0; i < to.size(); ++i)
    for (std::size_t k = 0; k < 3; ++k) out[3 * to[i] + k] = values[3 * i + k];
  return out;
}

// Vertex i renumbered as to[i] (a permutation).
inline TriangleMesh renumbered(const TriangleMesh& mesh, const std::vector<uint32_t>& to) {
  TriangleMesh out = mesh;
  out.positions = renumbered_values(mesh.positions, to);
  for (uint32_t& corner : out.triangles) corner = to[corner];
  return out;
}

inline std::vector<uint32_t> step_numbering(uint32_t n, uint32_t step) {
  std::vector<uint32_t> to(n);
  for (uint32_t i = 0; i < n; ++i) to[i] = renumbered_index(i, step, n);
  return to;
}

// A numbering at random (a fixed seed): unlike renumbered_index's, which maps each offset between
// two vertices to one offset and so keeps a mesh's bands (spring_lanes.hpp) bands, it leaves the
// general path's layout nothing in order.
inline std::vector<uint32_t> shuffled_numbering(uint32_t n, uint32_t seed) {
  std::vector<uint32_t> to(n);
  for (uint32_t i = 0; i < n; ++i) to[i] = i;
  uint32_t state = seed;
  for (uint32_t i = n; i > 1; --i) {  // Fisher-Yates, a 32-bit LCG
    state = state * 1664525u + 1013904223u;
    std::swap(to[i - 1], to[state % i]);
  }
  return to;
}

// The classic RK4 as a Runge-Kutta-Nystrom scheme (clothlab_rkn_scheme): what tests and
// benchmarks step a cloth's own step_rkn with.
inline const clothlab_rkn_scheme& rk4_scheme() {
  static constexpr double c[4] = {0, 0.5, 0.5, 1}, alpha[4] = {0, 0.5, 0.5, 1};
  static constexpr double x_coupling[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0.25, 0, 0, 0, 0, 0.5, 0};
  static constexpr double v_coupling[16] = {0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1, 0};
  static constexpr double x_weights[4] = {1.0 / 6, 1.0 / 6, 1.0 / 6, 0};
  static constexpr double v_weights[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  static constexpr clothlab_rkn_scheme scheme{sizeof scheme, 4,          c,         alpha,
                                              x_coupling,    v_coupling, x_weights, v_weights};
  return scheme;
}

}  // namespace clothlab::testing
