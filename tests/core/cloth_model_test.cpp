// The cloth as data: the mesh builder's springs against the grid builder's (a grid written as
// triangles must give the Provot springs), the rules on an irregular mesh and a disc, and the
// masses spread by area.
#include <clothlab/ext/topology.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

#include "cloth_test_support.hpp"
#include "mesh_test_support.hpp"

namespace clothlab {
namespace {

using testing::Diagonals;

struct SpringRecord {
  uint32_t i, j;
  uint8_t family;
  double rest, ks, kd;
};

std::vector<SpringRecord> sorted_springs(const ClothModel& model) {
  std::vector<SpringRecord> springs;
  for (std::size_t s = 0; s < model.spring_count(); ++s)
    springs.push_back({model.first[s], model.second[s], model.family[s], model.rest_length[s],
                       model.ks[s], model.kd[s]});
  std::sort(springs.begin(), springs.end(), [](const SpringRecord& l, const SpringRecord& r) {
    return std::tie(l.i, l.j) < std::tie(r.i, r.j);
  });
  return springs;
}

std::size_t count_family(const ClothModel& model, uint8_t family) {
  return static_cast<std::size_t>(std::count(model.family.begin(), model.family.end(), family));
}

// The same pairs, families, ks and kd; rest lengths to rounding (the grid's come from the
// spacing, the mesh's from the positions' differences).
void expect_same_springs(const ClothModel& grid, const ClothModel& mesh) {
  const std::vector<SpringRecord> expected = sorted_springs(grid), got = sorted_springs(mesh);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t s = 0; s < got.size(); ++s) {
    SCOPED_TRACE("spring " + std::to_string(expected[s].i) + "-" + std::to_string(expected[s].j));
    ASSERT_EQ(got[s].i, expected[s].i);
    ASSERT_EQ(got[s].j, expected[s].j);
    EXPECT_EQ(got[s].family, expected[s].family);
    EXPECT_NEAR(got[s].rest, expected[s].rest, 1e-12 * expected[s].rest);
    EXPECT_EQ(got[s].ks, expected[s].ks);
    EXPECT_EQ(got[s].kd, expected[s].kd);
  }
}

TEST(ClothModel, GridWrittenAsTrianglesGivesTheProvotSprings) {
  const uint32_t shapes[][2] = {{2, 2}, {2, 5}, {5, 2}, {3, 3}, {6, 5}, {9, 7}};
  for (const auto& shape : shapes) {
    const Scene scene = testing::busy_scene(shape[0], shape[1]);  // tilted, offset, every family
    const auto grid = build_grid_model(scene);
    for (Diagonals diagonals : {Diagonals::Falling, Diagonals::Rising, Diagonals::Alternating}) {
      SCOPED_TRACE(std::to_string(shape[0]) + "x" + std::to_string(shape[1]) + " diagonals " +
                   std::to_string(static_cast<int>(diagonals)));
      const auto mesh = build_mesh_model(testing::grid_mesh(scene, diagonals), scene);
      expect_same_springs(*grid, *mesh);
      EXPECT_EQ(mesh->pinned, grid->pinned);
      EXPECT_FALSE(mesh->grid.has_value());
    }
  }
}

TEST(ClothModel, FamiliesWithoutStiffnessOrDampingAreLeftOut) {
  Scene scene = testing::busy_scene(5, 6);
  scene.shear = {0.0, 0.0};
  const auto mesh = build_mesh_model(testing::grid_mesh(scene, Diagonals::Rising), scene);
  expect_same_springs(*build_grid_model(scene), *mesh);
  EXPECT_EQ(count_family(*mesh, CLOTHLAB_SPRING_SHEAR), 0u);
}

TEST(ClothModel, IrregularMeshBendsAcrossEverySharedEdge) {
  const Scene scene = testing::busy_scene(2, 2);  // the families' laws only
  const TriangleMesh mesh = testing::irregular_mesh(12, 10);
  const auto model = build_mesh_model(mesh, scene);
  // Every edge structural (no rectangles, so no shear); one flexion spring per pair of corners
  // opposite a shared edge (around a vertex of four triangles two edges share a pair).
  std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> opposite_of_edge;
  for (std::size_t t = 0; t < mesh.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = mesh.triangles[t + k], b = mesh.triangles[t + (k + 1) % 3];
      opposite_of_edge[{std::min(a, b), std::max(a, b)}].push_back(mesh.triangles[t + (k + 2) % 3]);
    }
  std::set<std::pair<uint32_t, uint32_t>> bend_pairs;
  for (const auto& [edge, opposite] : opposite_of_edge)
    if (opposite.size() == 2)
      bend_pairs.insert({std::min(opposite[0], opposite[1]), std::max(opposite[0], opposite[1])});
  EXPECT_EQ(count_family(*model, CLOTHLAB_SPRING_STRUCTURAL), opposite_of_edge.size());
  EXPECT_EQ(count_family(*model, CLOTHLAB_SPRING_SHEAR), 0u);
  EXPECT_EQ(count_family(*model, CLOTHLAB_SPRING_FLEXION), bend_pairs.size());
  for (std::size_t s = 0; s < model->spring_count(); ++s) {
    EXPECT_LT(model->first[s], model->second[s]);
    if (model->family[s] == CLOTHLAB_SPRING_FLEXION) {
      EXPECT_EQ(bend_pairs.count({model->first[s], model->second[s]}), 1u);
    }
  }
}

TEST(ClothModel, DiscBendsAlongItsStraightLinesAndAcrossTheRest) {
  const Scene scene = testing::busy_scene(2, 2);
  const auto model = build_mesh_model(testing::disc_mesh(6, 0.1), scene);
  EXPECT_EQ(model->particle_count, 1u + 3u * 6 * 7);  // 1 + sum 6k
  EXPECT_EQ(count_family(*model, CLOTHLAB_SPRING_SHEAR), 0u);
  // The six spokes from the centre are straight lines of edges: each inner vertex on one gets a
  // flexion spring along it.
  std::size_t through_centre = 0;
  for (std::size_t s = 0; s < model->spring_count(); ++s)
    if (model->family[s] == CLOTHLAB_SPRING_FLEXION && model->first[s] == 0) ++through_centre;
  EXPECT_EQ(through_centre, 6u);  // centre to ring 2 along each spoke
  EXPECT_GT(count_family(*model, CLOTHLAB_SPRING_FLEXION), model->particle_count);
}

TEST(ClothModel, MassesAreSpreadByAreaAndPinsHaveNoInverseMass) {
  Scene scene = testing::busy_scene(2, 2);
  scene.pinned = {0, 5};
  const auto model =
      build_mesh_model(testing::grid_mesh(testing::bare_scene(4, 4), Diagonals::Rising), scene);
  const double total = std::accumulate(model->masses.begin(), model->masses.end(), 0.0);
  EXPECT_NEAR(total, scene.total_mass, 1e-14);
  // Cells split one way: an inner vertex touches 6 triangles, the top-left corner 1.
  EXPECT_NEAR(model->masses[5] / model->masses[6], 1.0, 1e-14);
  EXPECT_NEAR(6 * model->masses[0] / model->masses[5], 1.0, 1e-14);
  EXPECT_EQ(model->inverse_masses[0], 0.0);
  EXPECT_EQ(model->inverse_masses[5], 0.0);
  EXPECT_GT(model->inverse_masses[1], 0.0);
}

TEST(ClothModel, GivenMassesAreKept) {
  TriangleMesh mesh = testing::disc_mesh(2, 0.1);
  mesh.masses.assign(mesh.positions.size() / 3, 0.01);
  mesh.masses[3] = 0.5;
  const auto model = build_mesh_model(mesh, testing::busy_scene(2, 2));
  EXPECT_EQ(model->masses, mesh.masses);
  EXPECT_EQ(model->inverse_masses[3], 2.0);
}

TEST(ClothModel, PinOutsideTheMeshIsRefused) {
  Scene scene = testing::busy_scene(2, 2);
  scene.pinned = {7};
  try {
    (void)build_mesh_model(testing::disc_mesh(1, 0.1), scene);
    FAIL() << "a pin past the 7 vertices was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "scene.pinned = 7: allowed indices < the particle count 7");
  }
}

TEST(ClothModel, AdjacencyListsEverySpringAtBothEnds) {
  const auto model = build_mesh_model(testing::irregular_mesh(5, 6), testing::busy_scene(2, 2));
  ASSERT_EQ(model->adjacency_offsets.size(), model->particle_count + 1u);
  EXPECT_EQ(model->adjacent_springs.size(), 2 * model->spring_count());
  for (uint32_t i = 0; i < model->particle_count; ++i)
    for (uint32_t e = model->adjacency_offsets[i]; e < model->adjacency_offsets[i + 1]; ++e) {
      const uint32_t s = model->adjacent_springs[e];
      EXPECT_TRUE(model->first[s] == i || model->second[s] == i);
      if (e > model->adjacency_offsets[i]) {
        EXPECT_LT(model->adjacent_springs[e - 1], s);
      }
    }
}

}  // namespace
}  // namespace clothlab
