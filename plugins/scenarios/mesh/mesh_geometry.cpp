#include "mesh_geometry.hpp"

#include <algorithm>
#include <clothlab/sdk/error.hpp>
#include <cmath>
#include <cstdio>
#include <unordered_map>

namespace clothlab::builtin {

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, source + ": " + what);
}

std::string triangle_text(const TriangleMesh& mesh, size_t t) {
  const auto& c = mesh.triangles[t];
  return "triangle " + std::to_string(t) + " (vertices " + std::to_string(c[0]) + ", " +
         std::to_string(c[1]) + ", " + std::to_string(c[2]) + ")";
}

std::array<double, 3> minus(const std::array<double, 3>& a, const std::array<double, 3>& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}

double squared(const std::array<double, 3>& a) { return a[0] * a[0] + a[1] * a[1] + a[2] * a[2]; }

// Twice the triangle's area, and its longest edge squared.
std::pair<double, double> doubled_area_and_longest(const TriangleMesh& mesh, size_t t) {
  const auto& c = mesh.triangles[t];
  const auto& p = mesh.positions;
  const auto u = minus(p[c[1]], p[c[0]]), v = minus(p[c[2]], p[c[0]]), w = minus(p[c[2]], p[c[1]]);
  const std::array<double, 3> n = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                                   u[0] * v[1] - u[1] * v[0]};
  return {std::sqrt(squared(n)), std::max({squared(u), squared(v), squared(w)})};
}

}  // namespace

void check_mesh_geometry(const TriangleMesh& mesh, const std::string& source) {
  if (mesh.triangles.empty())
    fail(source, "empty mesh (" + std::to_string(mesh.positions.size()) + " vertices, " +
                     std::to_string(mesh.triangles.size()) +
                     " triangles); allowed: at least 1 "
                     "triangle");
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const auto& p = mesh.positions[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      char text[200];
      std::snprintf(text, sizeof text, "vertex %zu = (%g, %g, %g) is not finite", i, p[0], p[1],
                    p[2]);
      fail(source, text);
    }
  }
  const uint32_t count = static_cast<uint32_t>(mesh.positions.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t corner : mesh.triangles[t])
      if (corner >= count)
        fail(source, triangle_text(mesh, t) + " uses vertex " + std::to_string(corner) + " of " +
                         std::to_string(count) + " (index out of range)");
  // A triangle is degenerate when a corner repeats or its area is negligible beside its size
  // (its height under 1e-9 of its longest edge): its normal and its springs are undefined.
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& c = mesh.triangles[t];
    const auto [area2, longest2] = doubled_area_and_longest(mesh, t);
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2] || !(area2 > 1e-9 * longest2))
      fail(source, triangle_text(mesh, t) + " is degenerate (zero area)");
  }
  // Each directed edge (a, b) of a triangle; a manifold, consistently wound mesh has every
  // undirected edge in one or two triangles, the two in opposite directions.
  std::unordered_map<uint64_t, size_t> directed;
  std::unordered_map<uint64_t, int> uses;
  directed.reserve(3 * mesh.triangles.size());
  uses.reserve(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& c = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = c[k], b = c[(k + 1) % 3];
      const uint64_t undirected = (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
      if (++uses[undirected] > 2)
        fail(source, "edge " + std::to_string(std::min(a, b)) + "-" +
                         std::to_string(std::max(a, b)) +
                         " is shared by more than two triangles "
                         "(non-manifold), the third is " +
                         triangle_text(mesh, t));
      const auto [it, added] = directed.try_emplace((uint64_t{a} << 32) | b, t);
      if (!added)
        fail(source, triangle_text(mesh, it->second) + " and " + triangle_text(mesh, t) +
                         " wind their shared edge the same way; allowed: one winding for the "
                         "whole mesh (recalculate the normals outside)");
    }
  }
}

}  // namespace clothlab::builtin
