// validate_triangle_mesh: one line naming what is wrong for each kind of bad mesh, "" for a good
// one; build_mesh_model refuses with the same line.
#include <gtest/gtest.h>

#include <clothlab/core/triangle_mesh.hpp>
#include <limits>
#include <stdexcept>
#include <vector>

#include "cloth_test_support.hpp"
#include "mesh_test_support.hpp"

namespace clothlab {
namespace {

// Two triangles forming a unit square: 0 (0,0), 1 (1,0), 2 (1,1), 3 (0,1).
TriangleMesh square() { return {{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}, {0, 1, 2, 0, 2, 3}, {}}; }

std::string fault(const TriangleMesh& mesh, uint32_t max_particles = kMaxMeshParticles) {
  return validate_triangle_mesh(mesh.positions, mesh.triangles, mesh.masses, max_particles);
}

TEST(MeshValidation, AcceptsGoodMeshes) {
  EXPECT_EQ(fault(square()), "");
  EXPECT_EQ(fault(testing::disc_mesh(4, 0.1)), "");
  EXPECT_EQ(fault(testing::irregular_mesh(6, 7)), "");
}

TEST(MeshValidation, NamesEachFault) {
  EXPECT_EQ(fault({}),
            "empty mesh: 0 vertices, 0 triangles (allowed: at least 3 vertices and 1 "
            "triangle)");
  TriangleMesh no_triangles = square();
  no_triangles.triangles.clear();
  EXPECT_EQ(fault(no_triangles),
            "empty mesh: 4 vertices, 0 triangles (allowed: at least 3 vertices and 1 triangle)");
  TriangleMesh ragged = square();
  ragged.positions.pop_back();
  EXPECT_EQ(fault(ragged), "positions: 11 values, not 3 per vertex");
  TriangleMesh ragged_triangles = square();
  ragged_triangles.triangles.pop_back();
  EXPECT_EQ(fault(ragged_triangles), "triangles: 5 indices, not 3 per triangle");
  EXPECT_EQ(fault(square(), 3), "4 vertices: over the limit of 3 particles");

  TriangleMesh not_finite = square();
  not_finite.positions[7] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(fault(not_finite), "vertex 2: coordinate y = nan (allowed: finite)");
  not_finite.positions[7] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(fault(not_finite), "vertex 2: coordinate y = inf (allowed: finite)");

  TriangleMesh out_of_range = square();
  out_of_range.triangles[4] = 4;
  EXPECT_EQ(fault(out_of_range), "triangle 1: vertex index 4 out of range (4 vertices)");

  TriangleMesh repeated = square();
  repeated.triangles[5] = 0;
  EXPECT_EQ(fault(repeated), "triangle 1: corners 0, 2, 0 repeat a vertex (degenerate)");

  TriangleMesh flat = square();
  flat.positions[9] = 0.5;  // vertex 3 onto the diagonal 0-2
  flat.positions[10] = 0.5;
  EXPECT_EQ(fault(flat), "triangle 1: zero area (corners 0, 2, 3 in a line or at one point)");

  TriangleMesh unreferenced = square();
  unreferenced.positions.insert(unreferenced.positions.end(), {2, 2, 0});
  EXPECT_EQ(fault(unreferenced), "vertex 4: in no triangle (unreferenced)");

  TriangleMesh fin = square();  // a third triangle on the edge 0-2
  fin.positions.insert(fin.positions.end(), {0.5, 0.5, 1});
  fin.triangles.insert(fin.triangles.end(), {0, 2, 4});
  EXPECT_EQ(fault(fin), "edge 0-2: in more than two triangles (0, 1, 2): non-manifold");

  TriangleMesh masses = square();
  masses.masses = {1, 1, 1};
  EXPECT_EQ(fault(masses), "masses: 3 values for 4 vertices (allowed: one per vertex, or none)");
  masses.masses = {1, 1, 0, 1};
  EXPECT_EQ(fault(masses), "vertex 2: mass 0.000000 (allowed: finite, > 0 kg)");
}

TEST(MeshValidation, BuilderRefusesWithTheSameLine) {
  TriangleMesh repeated = square();
  repeated.triangles[5] = 0;
  try {
    (void)build_mesh_model(repeated, testing::busy_scene(2, 2));
    FAIL() << "a degenerate triangle was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "mesh: triangle 1: corners 0, 2, 0 repeat a vertex (degenerate)");
  }
}

}  // namespace
}  // namespace clothlab
