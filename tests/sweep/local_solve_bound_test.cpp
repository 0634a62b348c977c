// The m / h^2 bound of a local solver (local_solve_bound.hpp) worked out by hand.
#include "clothlab/analysis/local_solve_bound.hpp"

#include <gtest/gtest.h>

#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <numbers>

namespace clothlab::analysis {
namespace {

ClothModel grid(uint32_t side, double total_mass, double ks) {
  Scene scene;
  scene.rows = scene.cols = side;
  scene.total_mass = total_mass;
  scene.structural.ks = ks;
  scene.shear.ks = 10 * ks;  // not the warp/weft springs: the bound ignores them
  return *build_grid_model(scene);
}

TEST(LocalSolveBound, IsTheStepWhereMassOverStepSquaredReachesTheStiffness) {
  // 2 x 2 particles of 1 kg, ks = 14400 N/m: h <= sqrt(1 / 14400) = 1/120 s, 2 substeps at 60 Hz.
  const LocalSolveBound bound = local_solve_bound(grid(2, 4.0, 14400.0));
  EXPECT_DOUBLE_EQ(bound.particle_mass, 1.0);
  EXPECT_DOUBLE_EQ(bound.stiffness, 14400.0);
  EXPECT_NEAR(bound.dt_max, 1.0 / 120, 1e-15);
  EXPECT_EQ(bound.substeps_per_frame(60), 2u);  // exactly 2: not rounded up to 3
  EXPECT_EQ(bound.substeps_per_frame(50), 3u);  // 2.4 -> 3
  EXPECT_EQ(bound.substeps_per_frame(240), 1u);
}

TEST(LocalSolveBound, GrowsWithTheMeshAsTheIssueEstimates) {
  // A cloth of fixed mass and per-spring ks: each particle is n times lighter on n times the
  // particles, so the substeps grow as the side (3 x from 100 x 100 to 300 x 300).
  const uint32_t at_100 = local_solve_bound(grid(100, 0.15, 6000.0)).substeps_per_frame(60);
  const uint32_t at_300 = local_solve_bound(grid(300, 0.15, 6000.0)).substeps_per_frame(60);
  EXPECT_EQ(at_100, 334u);  // 1 / (60 sqrt(1.5e-5 / 6000)) = 333.3
  EXPECT_EQ(at_300, 1000u);
  // No warp/weft stiffness: no bound.
  EXPECT_TRUE(std::isinf(local_solve_bound(grid(10, 1.0, 0.0)).dt_max));
  EXPECT_EQ(local_solve_bound(grid(10, 1.0, 0.0)).substeps_per_frame(60), 1u);
}

TEST(LocalSolveBound, OnAMeshIsTheMedianStructuralSprings) {
  // A disc (rings of 6k particles, spacing 0.1 m) of 1 kg under one ks: masses by area differ
  // from particle to particle, so the bound is the median spring's sqrt(m / ks), not the
  // lightest particle's.
  Scene scene;
  scene.rows = scene.cols = 0;
  scene.total_mass = 1.0;
  scene.structural.ks = 100.0;
  TriangleMesh disc;
  disc.positions = {0, 0, 0};
  for (int j = 0; j < 6; ++j)
    disc.positions.insert(disc.positions.end(), {0.1 * std::cos(j * std::numbers::pi / 3),
                                                 0.1 * std::sin(j * std::numbers::pi / 3), 0.0});
  for (uint32_t j = 0; j < 6; ++j)
    disc.triangles.insert(disc.triangles.end(), {0, 1 + j, 1 + (j + 1) % 6});
  const auto model = build_mesh_model(disc, scene);
  // The hub holds a third of all six triangles (1/3 kg); each rim particle a third of two
  // (1/9 kg). Six spokes (mean 2/9 kg) and six rim edges (1/9 kg): the median (index 6 of 12)
  // is a spoke's.
  const LocalSolveBound bound = local_solve_bound(*model);
  EXPECT_NEAR(bound.particle_mass, 2.0 / 9, 1e-12);
  EXPECT_DOUBLE_EQ(bound.stiffness, 100.0);
  EXPECT_NEAR(bound.dt_max, std::sqrt(2.0 / 900), 1e-12);
}

}  // namespace
}  // namespace clothlab::analysis
