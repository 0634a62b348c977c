#include <gtest/gtest.h>

#include <clothlab/core/cloth.hpp>
#include <cstdint>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

using testing::seed_equation_2_2;

TEST(SpringCounts, MatchSeedEquationForGridsOfAtLeastTwoByTwo) {
  const uint32_t shapes[][2] = {{2, 2}, {2, 3},   {3, 2},   {3, 3},
                                {5, 4}, {17, 13}, {50, 50}, {300, 300}};
  for (const auto& shape : shapes) {
    const SpringCounts expected = seed_equation_2_2(shape[0], shape[1]);
    const SpringCounts counted = count_springs(shape[0], shape[1]);
    EXPECT_EQ(counted.structural, expected.structural) << shape[0] << "x" << shape[1];
    EXPECT_EQ(counted.shear, expected.shear) << shape[0] << "x" << shape[1];
    EXPECT_EQ(counted.flexion, expected.flexion) << shape[0] << "x" << shape[1];
  }
}

TEST(SpringCounts, SeedFigures) {
  EXPECT_EQ(count_springs(300, 300).total(), 537002u);
  EXPECT_EQ(count_springs(50, 50).total(), 14502u);  // seed §2.1.3, 50^2 mesh
}

TEST(SpringCounts, SingleParticleHasNoSprings) {
  const SpringCounts counts = count_springs(1, 1);
  EXPECT_EQ(counts.structural, 0u);
  EXPECT_EQ(counts.shear, 0u);
  EXPECT_EQ(counts.flexion, 0u);
}

TEST(SpringCounts, TwoByOneIsOneStructuralSpring) {
  const SpringCounts counts = count_springs(2, 1);
  EXPECT_EQ(counts.structural, 1u);
  EXPECT_EQ(counts.shear, 0u);
  EXPECT_EQ(counts.flexion, 0u);
}

TEST(SpringCounts, OneByFiveIsAChain) {
  const SpringCounts counts = count_springs(1, 5);
  EXPECT_EQ(counts.structural, 4u);  // neighbours
  EXPECT_EQ(counts.shear, 0u);
  EXPECT_EQ(counts.flexion, 3u);  // every second particle
}

}  // namespace
}  // namespace clothlab
