// validate_triangle_mesh: the one check every mesh reader and builder runs.
#include <algorithm>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <string>

#include "mesh_edges.hpp"

namespace clothlab {
namespace {

std::string text(double value) { return std::isnan(value) ? "nan" : std::to_string(value); }

}  // namespace

std::string validate_triangle_mesh(std::span<const double> positions,
                                   std::span<const uint32_t> triangles,
                                   std::span<const double> masses, uint32_t max_particles) {
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
             text(positions[i]) + " (allowed: finite)";
  if (!masses.empty()) {
    if (masses.size() != vertices)
      return "masses: " + std::to_string(masses.size()) + " values for " +
             std::to_string(vertices) + " vertices (allowed: one per vertex, or none)";
    for (std::size_t i = 0; i < vertices; ++i)
      if (!(std::isfinite(masses[i]) && masses[i] > 0.0))
        return "vertex " + std::to_string(i) + ": mass " + text(masses[i]) +
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
    const detail::TriangleShape shape = detail::triangle_shape(positions, corner);
    if (!(shape.double_area > 1e-10 * shape.longest_edge_squared))
      return "triangle " + std::to_string(t) + ": zero area (corners " + std::to_string(corner[0]) +
             ", " + std::to_string(corner[1]) + ", " + std::to_string(corner[2]) +
             " in a line or at one point)";
  }
  for (std::size_t i = 0; i < vertices; ++i)
    if (!referenced[i]) return "vertex " + std::to_string(i) + ": in no triangle (unreferenced)";
  const std::vector<detail::EdgeUse> uses = detail::edge_uses(triangles);
  for (std::size_t e = 0; e + 2 < uses.size(); ++e)
    if (uses[e].key == uses[e + 2].key)
      return "edge " + std::to_string(uses[e].a()) + "-" + std::to_string(uses[e].b()) +
             ": in more than two triangles (" + std::to_string(uses[e].triangle) + ", " +
             std::to_string(uses[e + 1].triangle) + ", " + std::to_string(uses[e + 2].triangle) +
             "): non-manifold";
  return {};
}

}  // namespace clothlab
