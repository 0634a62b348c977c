// The m / h^2 bound of a local solver (local_solve_bound.hpp) worked out by hand.
#include "clothlab/analysis/local_solve_bound.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace clothlab::analysis {
namespace {

Scene grid(uint32_t side, double total_mass, double ks) {
  Scene scene;
  scene.rows = scene.cols = side;
  scene.total_mass = total_mass;
  scene.structural.ks = ks;
  scene.shear.ks = 10 * ks;  // not the warp/weft springs: the bound ignores them
  return scene;
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

}  // namespace
}  // namespace clothlab::analysis
