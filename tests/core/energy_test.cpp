// Energy and stretch of a single spring (2x1 grid, rest length 1, 1 kg per particle)
// stretched to 1.5 m, worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

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

namespace clothlab {
namespace {

TEST(Energy, SingleParticleFallsWithoutSprings) {
  Scene scene = testing::bare_scene(1, 1);
  scene.gravity = {0, -10, 0};
  Cloth cloth(scene, Precision::Float64, {});
  cloth.set_state({0, -2, 0}, {0, -3, 0});
  EXPECT_NEAR(cloth.energy().gravity, -20.0, 1e-12);  // 1 kg, 2 m below its start
  EXPECT_NEAR(cloth.energy().kinetic, 4.5, 1e-12);
  EXPECT_EQ(cloth.energy().spring, 0.0);
  EXPECT_EQ(cloth.max_stretch(), 1.0);  // no springs: unstretched by definition
}

TEST(Energy, LargeThreadedClothMatchesHandValue) {
  // Every structural spring of a 100x80 grid stretched by the same 10% (uniform scaling),
  // shear and flexion likewise: spring energy = sum over families of count * ks/2 (0.1 L0)^2.
  Scene scene = testing::bare_scene(100, 80);
  scene.structural = {10.0, 0.0};
  scene.shear = {4.0, 0.0};
  scene.flexion = {2.0, 0.0};
  PipelineOptions options;
  options.threads = 2;
  Cloth cloth(scene, Precision::Float64, options);
  std::vector<double> x, v(3 * 8000, 0.0);
  cloth.positions(x);
  for (double& component : x) component *= 1.1;
  cloth.set_state(x, v);
  const SpringCounts counts = count_springs(100, 80);
  const double horizontal = 100.0 * 79, vertical = 99.0 * 80;  // unit rest lengths
  const double expected = 0.5 * 10.0 * 0.01 * (horizontal + vertical) +
                          0.5 * 4.0 * 0.01 * 2.0 * counts.shear +   // rest sqrt(2): L0^2 = 2
                          0.5 * 2.0 * 0.01 * 4.0 * counts.flexion;  // rest 2: L0^2 = 4
  EXPECT_NEAR(cloth.energy().spring, expected, 1e-9 * expected);
  EXPECT_NEAR(cloth.max_stretch(), 1.1, 1e-12);
  EXPECT_NEAR(cloth.stretch().mean, 1.1, 1e-12);
}

TEST(Energy, MeanStretchAveragesOverEverySpring) {
  // 3x1 grid: two structural springs (rest 1) and one flexion spring (rest 2). Moving the last
  // particle from y = -2 to y = -3 stretches one structural spring to 2 and the flexion spring
  // to 1.5: mean (1 + 2 + 1.5) / 3 = 1.5, max 2.
  Scene scene = testing::bare_scene(3, 1);
  Cloth cloth(scene, Precision::Float64, {});
  cloth.set_state({0, 0, 0, 0, -1, 0, 0, -3, 0}, std::vector<double>(9, 0.0));
  EXPECT_NEAR(cloth.stretch().max, 2.0, 1e-12);
  EXPECT_NEAR(cloth.stretch().mean, 1.5, 1e-12);
  // The structural springs alone: (1 + 2) / 2.
  EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).mean, 1.5, 1e-12);
  EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max, 2.0, 1e-12);
}

TEST(Energy, StructuralStretchLeavesShearOut) {
  // A 2x2 square sheared into a rhombus keeps its four sides (structural, rest 1) and
  // lengthens one diagonal: all springs see that, the structural ones do not.
  Scene scene = testing::bare_scene(2, 2);
  Cloth cloth(scene, Precision::Float64, {});
  const double s = std::sqrt(0.5);  // top row shifted so that the sides stay 1
  cloth.set_state({0, 0, 0, 1, 0, 0, s, -s, 0, 1 + s, -s, 0}, std::vector<double>(12, 0.0));
  EXPECT_NEAR(cloth.stretch(Cloth::Springs::Structural).max, 1.0, 1e-12);
  EXPECT_GT(cloth.stretch().max, 1.2);
}

}  // namespace
}  // namespace clothlab

namespace clothlab {
namespace {

TEST(Energy, LongestSpringIsWhereTheMaximumIs) {
  // 4x5 unit grid, particle (2, 3) moved 0.3 m along the columns: the weft spring from (2, 2)
  // to (2, 3) is the longest (1.3; the warp springs at it 1.044, the shear spring from (1, 2)
  // 1.16, the flexion spring from (2, 1) 1.15).
  Scene scene = testing::bare_scene(4, 5);
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    Cloth cloth(scene, precision, {});
    std::vector<double> x, v(3 * 20, 0.0);
    cloth.positions(x);
    x[3 * (2 * 5 + 3)] += 0.3;
    cloth.set_state(x, v);
    for (Cloth::Springs springs : {Cloth::Springs::All, Cloth::Springs::Structural}) {
      const Cloth::LongestSpring longest = cloth.longest_spring(springs);
      EXPECT_NEAR(longest.ratio, 1.3, 1e-6);
      EXPECT_EQ(longest.ratio, cloth.stretch(springs).max);
      EXPECT_EQ(longest.row, 2u);
      EXPECT_EQ(longest.col, 2u);
      EXPECT_EQ(longest.row_step, 0u);
      EXPECT_EQ(longest.col_step, 1);
    }
  }
}

TEST(Energy, LongestSpringOfAllCanBeAShearSpring) {
  // The rhombus of StructuralStretchLeavesShearOut: the diagonal from (0, 0) to (1, 1) is the
  // longest (1.307 x its rest sqrt(2)); among the structural springs, all at 1, the first.
  Scene scene = testing::bare_scene(2, 2);
  Cloth cloth(scene, Precision::Float64, {});
  const double s = std::sqrt(0.5);
  cloth.set_state({0, 0, 0, 1, 0, 0, s, -s, 0, 1 + s, -s, 0}, std::vector<double>(12, 0.0));
  const Cloth::LongestSpring shear = cloth.longest_spring(Cloth::Springs::All);
  EXPECT_NEAR(shear.ratio, std::hypot(1 + s, s) / std::sqrt(2.0), 1e-12);
  EXPECT_EQ(shear.row, 0u);
  EXPECT_EQ(shear.col, 0u);
  EXPECT_EQ(shear.row_step, 1u);
  EXPECT_EQ(shear.col_step, 1);
  const Cloth::LongestSpring structural = cloth.longest_spring(Cloth::Springs::Structural);
  EXPECT_NEAR(structural.ratio, 1.0, 1e-12);
  EXPECT_EQ(structural.row_step + static_cast<uint32_t>(std::abs(structural.col_step)), 1u);
}

}  // namespace
}  // namespace clothlab
