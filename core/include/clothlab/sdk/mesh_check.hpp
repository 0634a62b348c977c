// The check every cloth mesh goes through, header-only so that a scenario can run it on what it
// read (and name its file) before the host runs it again on what the scenario describes: one
// rule for both. Also the edge list and triangle size it is built from, which the core's mesh
// builder derives springs with.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace clothlab::sdk {

// The most particles a mesh may have (as the largest grid, 4096 x 4096).
inline constexpr uint32_t max_mesh_particles = 4096u * 4096u;

namespace mesh {

// One triangle's use of an edge: the edge (a < b) as key a << 32 | b, the triangle, and the
// triangle's corner opposite the edge.
struct EdgeUse {
  uint64_t key;
  uint32_t triangle;
  uint32_t opposite;
  uint32_t a() const { return static_cast<uint32_t>(key >> 32); }
  uint32_t b() const { return static_cast<uint32_t>(key); }
};

inline uint64_t edge_key(uint32_t i, uint32_t j) {
  return i < j ? uint64_t{i} << 32 | j : uint64_t{j} << 32 | i;
}

// Sorted by edge, then by triangle: the uses of one edge are adjacent.
inline std::vector<EdgeUse> edge_uses(std::span<const uint32_t> triangles) {
  std::vector<EdgeUse> uses;
  uses.reserve(triangles.size());
  for (uint32_t t = 0; t < triangles.size() / 3; ++t) {
    const uint32_t* c = triangles.data() + 3 * std::size_t{t};
    uses.push_back({edge_key(c[0], c[1]), t, c[2]});
    uses.push_back({edge_key(c[1], c[2]), t, c[0]});
    uses.push_back({edge_key(c[2], c[0]), t, c[1]});
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& l, const EdgeUse& r) {
    return l.key != r.key ? l.key < r.key : l.triangle < r.triangle;
  });
  return uses;
}

struct TriangleShape {
  double double_area = 0;  // |e1 x e2|
  double longest_edge_squared = 0;
};

inline TriangleShape triangle_shape(std::span<const double> positions, const uint32_t* corner) {
  double edge[3][3];
  for (int e = 0; e < 3; ++e)
    for (int k = 0; k < 3; ++k)
      edge[e][k] = positions[3 * std::size_t{corner[(e + 1) % 3]} + k] -
                   positions[3 * std::size_t{corner[e]} + k];
  const double n[3] = {edge[0][1] * edge[2][2] - edge[0][2] * edge[2][1],
                       edge[0][2] * edge[2][0] - edge[0][0] * edge[2][2],
                       edge[0][0] * edge[2][1] - edge[0][1] * edge[2][0]};
  TriangleShape shape;
  shape.double_area = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  for (const auto& d : edge)
    shape.longest_edge_squared =
        std::max(shape.longest_edge_squared, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return shape;
}

inline std::string number_text(double value) {
  return std::isnan(value) ? "nan" : std::to_string(value);
}

}  // namespace mesh

// Why the mesh cannot be a cloth, in one line ("triangle 12: vertex index 40 out of range
// (40 vertices)"), or "" when it can: empty mesh, more than max_particles vertices, a positions
// or triangles array whose size is not a multiple of 3, a non-finite coordinate, an index out of
// range, a triangle with a repeated corner or (nearly) zero area, an edge of more than two
// triangles, a vertex in no triangle, masses of the wrong count or not finite and positive.
inline std::string validate_triangle_mesh(std::span<const double> positions,
                                          std::span<const uint32_t> triangles,
                                          std::span<const double> masses = {},
                                          uint32_t max_particles = max_mesh_particles) {
  using mesh::number_text;
  if (positions.size() % 3 != 0)
    return "positions: " + std::to_string(positions.size()) + " values, not 3 per vertex";
  if (triangles.size() % 3 != 0)
    return "triangles: " + std::to_string(triangles.size()) + " indices, not 3 per triangle";
  const std::size_t vertices = positions.size() / 3;
  const std::size_t faces = triangles.size() / 3;
  if (vertices == 0 || faces == 0)
    return "empty mesh: " + std::to_string(vertices) + " vertices, " + std::to_string(faces) +
           " triangles (allowed: at least 3 vertices and 1 triangle)";
  if (vertices > max_particles)
    return std::to_string(vertices) + " vertices: over the limit of " +
           std::to_string(max_particles) + " particles";
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!std::isfinite(positions[i]))
      return "vertex " + std::to_string(i / 3) + ": coordinate " + "xyz"[i % 3] + " = " +
             number_text(positions[i]) + " (allowed: finite)";
  if (!masses.empty()) {
    if (masses.size() != vertices)
      return "masses: " + std::to_string(masses.size()) + " values for " +
             std::to_string(vertices) + " vertices (allowed: one per vertex, or none)";
    for (std::size_t i = 0; i < vertices; ++i)
      if (!(std::isfinite(masses[i]) && masses[i] > 0.0))
        return "vertex " + std::to_string(i) + ": mass " + number_text(masses[i]) +
               " (allowed: finite, > 0 kg)";
  }
  std::vector<uint8_t> referenced(vertices, 0);
  for (std::size_t t = 0; t < faces; ++t) {
    const uint32_t* corner = triangles.data() + 3 * t;
    for (int k = 0; k < 3; ++k) {
      if (corner[k] >= vertices)
        return "triangle " + std::to_string(t) + ": vertex index " + std::to_string(corner[k]) +
               " out of range (" + std::to_string(vertices) + " vertices)";
      referenced[corner[k]] = 1;
    }
    if (corner[0] == corner[1] || corner[1] == corner[2] || corner[0] == corner[2])
      return "triangle " + std::to_string(t) + ": corners " + std::to_string(corner[0]) + ", " +
             std::to_string(corner[1]) + ", " + std::to_string(corner[2]) +
             " repeat a vertex (degenerate)";
    const mesh::TriangleShape shape = mesh::triangle_shape(positions, corner);
    if (!(shape.double_area > 1e-10 * shape.longest_edge_squared))
      return "triangle " + std::to_string(t) + ": zero area (corners " + std::to_string(corner[0]) +
             ", " + std::to_string(corner[1]) + ", " + std::to_string(corner[2]) +
             " in a line or at one point)";
  }
  for (std::size_t i = 0; i < vertices; ++i)
    if (!referenced[i]) return "vertex " + std::to_string(i) + ": in no triangle (unreferenced)";
  const std::vector<mesh::EdgeUse> uses = mesh::edge_uses(triangles);
  for (std::size_t e = 0; e + 2 < uses.size(); ++e)
    if (uses[e].key == uses[e + 2].key)
      return "edge " + std::to_string(uses[e].a()) + "-" + std::to_string(uses[e].b()) +
             ": in more than two triangles (" + std::to_string(uses[e].triangle) + ", " +
             std::to_string(uses[e + 1].triangle) + ", " + std::to_string(uses[e + 2].triangle) +
             "): non-manifold";
  return {};
}

}  // namespace clothlab::sdk
