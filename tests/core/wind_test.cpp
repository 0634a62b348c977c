// Wind on one grid cell of unit side in the xy plane (corners a=(0,0) b=(1,0) c=(0,-1)
// d=(1,-1), triangles abc and bdc, area 1/2 each, mass 1 per particle). Hand values:
// each triangle gets strength * area * (n_hat . w) n_hat, a third to each of its corners.
#include <gtest/gtest.h>

#include <cmath>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

using testing::acceleration;
using testing::bare_scene;

Scene windy_cell(Vec3 direction, double strength) {
  Scene scene = bare_scene(2, 2);
  scene.wind_direction = direction;
  scene.wind_strength = strength;
  return scene;
}

TEST(Wind, HeadOnPressureOnAFlatCell) {
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    Cloth cloth(windy_cell({0, 0, 1}, 6.0), precision, {});
    const std::vector<double> a =
        precision == Precision::Float32 ? acceleration<float>(cloth) : acceleration<double>(cloth);
    // Each triangle: 6 * 0.5 * 1 = 3 N along z; a third per corner. a and d belong to
    // one triangle, b and c to both.
    const double expected_z[] = {1.0, 2.0, 2.0, 1.0};
    for (int i = 0; i < 4; ++i) {
      EXPECT_NEAR(a[3 * i + 0], 0.0, 1e-6) << to_string(precision);
      EXPECT_NEAR(a[3 * i + 1], 0.0, 1e-6) << to_string(precision);
      EXPECT_NEAR(a[3 * i + 2], expected_z[i], 1e-6) << to_string(precision);
    }
    EXPECT_EQ(cloth.counters().normals_computed, 2u);
  }
}

TEST(Wind, ObliqueWindPushesAlongTheNormalOnly) {
  // Only n . w = 0.8 matters: the in-plane part of the wind exerts no force.
  Cloth cloth(windy_cell({0, 0.6, 0.8}, 6.0), Precision::Float64, {});
  const std::vector<double> a = acceleration<double>(cloth);
  const double expected_z[] = {0.8, 1.6, 1.6, 0.8};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(a[3 * i + 0], 0.0, 1e-12);
    EXPECT_NEAR(a[3 * i + 1], 0.0, 1e-12);
    EXPECT_NEAR(a[3 * i + 2], expected_z[i], 1e-12);
  }
}

TEST(Wind, TiltedTriangle) {
  Cloth cloth(windy_cell({0, 0, 1}, 6.0), Precision::Float64, {});
  // Lift d to (1, -1, 1). Triangle bdc: n = (d - b) x (c - b) = (0,-1,1) x (-1,-1,0)
  // = (1, -1, -1), area sqrt(3)/2, n_hat . w = -1/sqrt(3), so
  // F = 6 * sqrt(3)/2 * (-1/sqrt(3)) * (1,-1,-1)/sqrt(3) = sqrt(3) * (-1, 1, 1);
  // a third per corner: (-1, 1, 1)/sqrt(3). Triangle abc stays flat: (0, 0, 1) per corner.
  cloth.set_state({0, 0, 0, 1, 0, 0, 0, -1, 0, 1, -1, 1}, std::vector<double>(12, 0.0));
  const std::vector<double> a = acceleration<double>(cloth);
  const double s = 1.0 / std::sqrt(3.0);
  const double expected[4][3] = {{0, 0, 1}, {-s, s, 1 + s}, {-s, s, 1 + s}, {-s, s, s}};
  for (int i = 0; i < 4; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[3 * i + k], expected[i][k], 1e-12) << i << "," << k;
  }
}

TEST(Wind, NoWindStageWithoutWind) {
  Scene scene = windy_cell({0, 0, 1}, 0.0);
  Cloth cloth(scene, Precision::Float32, {});
  const std::vector<double> a = acceleration<float>(cloth);
  for (double component : a) EXPECT_EQ(component, 0.0);
  EXPECT_EQ(cloth.counters().normals_computed, 0u);
}

}  // namespace
}  // namespace clothlab
