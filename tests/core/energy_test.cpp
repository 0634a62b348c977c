// Energy and stretch of a single spring (2x1 grid, rest length 1, 1 kg per particle)
// stretched to 1.5 m, worked out by hand.
#include <gtest/gtest.h>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

TEST(Energy, StretchedSingleSpring) {
  Scene scene = testing::bare_scene(2, 1);
  scene.structural = {10.0, 3.0};
  scene.gravity = {0, -9.81, 0};
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    Cloth cloth(scene, precision, {});
    // Particle 1 starts at (0, -1, 0); move it to (0, -1.5, 0) rising at 2 m/s.
    cloth.set_state({0, 0, 0, 0, -1.5, 0}, {0, 0, 0, 0, 2, 0});
    const Cloth::Energy energy = cloth.energy();
    EXPECT_NEAR(energy.spring, 0.5 * 10.0 * 0.5 * 0.5, 1e-6);  // 1.25 J
    EXPECT_NEAR(energy.kinetic, 0.5 * 1.0 * 2.0 * 2.0, 1e-6);  // 2 J
    EXPECT_NEAR(energy.gravity, -1.0 * 9.81 * 0.5, 1e-6);      // 0.5 m lower: -4.905 J
    EXPECT_NEAR(energy.total(), 1.25 + 2.0 - 4.905, 1e-6);
    EXPECT_NEAR(cloth.max_stretch(), 1.5, 1e-6);
  }
}

TEST(Energy, PinnedParticlesCarryNoEnergy) {
  Scene scene = testing::bare_scene(2, 1);
  scene.gravity = {0, -9.81, 0};
  scene.pinned = {1};
  Cloth cloth(scene, Precision::Float64, {});
  cloth.set_state({0, 0, 0, 0, -3, 0}, {0, 0, 0, 5, 0, 0});
  const Cloth::Energy energy = cloth.energy();
  EXPECT_EQ(energy.kinetic, 0.0);
  EXPECT_EQ(energy.gravity, 0.0);
}

TEST(Energy, InitialLayoutIsAtRest) {
  Scene scene = testing::bare_scene(6, 5);
  scene.structural = {100.0, 0.0};
  scene.shear = {50.0, 0.0};
  scene.flexion = {20.0, 0.0};
  scene.gravity = {0, -9.81, 0};
  Cloth cloth(scene, Precision::Float64, {});
  EXPECT_NEAR(cloth.energy().total(), 0.0, 1e-12);
  EXPECT_NEAR(cloth.max_stretch(), 1.0, 1e-12);
}

}  // namespace
}  // namespace clothlab
