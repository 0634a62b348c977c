#include "mesh_geometry.hpp"

#include <algorithm>
#include <clothlab/sdk/error.hpp>
#include <clothlab/sdk/mesh_check.hpp>
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

}  // namespace

void check_mesh_geometry(const TriangleMesh& mesh, const std::string& source) {
  // The host's own check, on the file's mesh, so that its error names the file.
  const std::string problem = sdk::validate_triangle_mesh(
      {mesh.positions.empty() ? nullptr : mesh.positions[0].data(), 3 * mesh.positions.size()},
      {mesh.triangles.empty() ? nullptr : mesh.triangles[0].data(), 3 * mesh.triangles.size()});
  if (!problem.empty()) fail(source, problem);
  // Each directed edge (a, b) of a triangle: in a consistently wound (manifold) mesh an edge of
  // two triangles is used once in each direction.
  std::unordered_map<uint64_t, size_t> directed;
  directed.reserve(3 * mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& c = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = c[k], b = c[(k + 1) % 3];
      const auto [it, added] = directed.try_emplace((uint64_t{a} << 32) | b, t);
      if (!added)
        fail(source, triangle_text(mesh, it->second) + " and " + triangle_text(mesh, t) +
                         " wind their shared edge the same way; allowed: one winding for the "
                         "whole mesh (recalculate the normals outside)");
    }
  }
}

}  // namespace clothlab::builtin
