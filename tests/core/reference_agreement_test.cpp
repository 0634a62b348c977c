// The stencil kernels against the seed-style reference (array of springs, scatter-add) on
// perturbed, moving states with every force on, both precisions, several grid shapes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cloth_test_support.hpp"
#include "reference_forces.hpp"

namespace clothlab {
namespace {

using testing::busy_scene;

template <class Real>
void expect_agreement(uint32_t rows, uint32_t cols, double relative_tolerance,
                      PipelineOptions options = {}) {
  const Scene scene = busy_scene(rows, cols);
  const Precision precision =
      sizeof(Real) == sizeof(float) ? Precision::Float32 : Precision::Float64;
  Cloth cloth(scene, precision, options);
  reference::ReferenceCloth<Real> reference(scene);

  // Perturb the layout by up to 20% of a cell and give every particle a velocity.
  std::mt19937 random(rows * 1000 + cols);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  std::vector<double> x, v(3 * std::size_t{rows} * cols);
  cloth.positions(x);
  for (double& component : x) component += jitter(random);
  for (double& component : v) component = 20 * jitter(random);
  cloth.set_state(x, v);
  cloth.positions(x);  // rounded to Real, exactly what both evaluate
  cloth.velocities(v);

  const std::vector<double> fast = testing::acceleration<Real>(cloth);
  std::vector<Real> xr(x.begin(), x.end()), vr(v.begin(), v.end()), ar(x.size());
  reference.acceleration(xr.data(), vr.data(), ar.data());

  double scale = 0.0;
  for (Real component : ar) scale = std::max(scale, std::abs(double{component}));
  ASSERT_GT(scale, 0.0);
  for (std::size_t e = 0; e < ar.size(); ++e) {
    ASSERT_NEAR(fast[e], ar[e], relative_tolerance * scale)
        << rows << "x" << cols << " particle " << e / 3 << " component " << e % 3;
  }
}

const uint32_t kShapes[][2] = {{1, 1}, {2, 1},   {1, 7},   {7, 1},  {3, 3},
                               {5, 4}, {17, 13}, {64, 48}, {80, 70}};

TEST(ReferenceAgreement, Float64) {
  for (const auto& shape : kShapes) expect_agreement<double>(shape[0], shape[1], 1e-12);
}

TEST(ReferenceAgreement, Float32) {
  for (const auto& shape : kShapes) expect_agreement<float>(shape[0], shape[1], 2e-5);
}

// Large enough to run threaded: row blocks of uneven size, each recomputing the two
// rows above it, and degenerate one-row and one-column grids.
TEST(ReferenceAgreement, ThreadedRowBlocks) {
  const uint32_t shapes[][2] = {{80, 70}, {4100, 1}, {1, 4100}, {97, 61}, {4100, 2}, {97, 9}};
  for (int threads : {2, 3, 5}) {
    PipelineOptions options;
    options.threads = threads;
    for (const auto& shape : shapes) {
      SCOPED_TRACE(::testing::Message() << threads << " threads");
      expect_agreement<double>(shape[0], shape[1], 1e-12, options);
      expect_agreement<float>(shape[0], shape[1], 2e-5, options);
    }
  }
}

TEST(ReferenceAgreement, WithoutVelocityForces) {
  const Scene scene = busy_scene(9, 11);
  PipelineOptions options;
  options.velocity_forces = false;
  Cloth cloth(scene, Precision::Float64, options);
  reference::ReferenceCloth<double> reference(scene);
  std::vector<double> x, v(3 * 99, 0.5), a(3 * 99);
  cloth.positions(x);
  x[3 * 40 + 2] += 0.1;  // bend the sheet so every family and the wind act
  cloth.set_state(x, v);
  const std::vector<double> fast = testing::acceleration<double>(cloth, false);
  reference.acceleration(x.data(), nullptr, a.data());
  for (std::size_t e = 0; e < a.size(); ++e) ASSERT_NEAR(fast[e], a[e], 1e-9) << e;
  EXPECT_EQ(cloth.counters().springs_damped, 0u);
  EXPECT_EQ(cloth.counters().springs_evaluated, count_springs(9, 11).total());
  EXPECT_EQ(cloth.counters().normals_computed, 2u * 8 * 10);
}

TEST(ReferenceAgreement, RepeatedEvaluationsGiveTheSameBits) {
  // Scratch left over from one evaluation must not leak into the next.
  PipelineOptions options;
  options.threads = 3;
  Cloth cloth(busy_scene(80, 70), Precision::Float64, options);
  const std::vector<double> first = testing::acceleration<double>(cloth);
  EXPECT_EQ(testing::acceleration<double>(cloth), first);
  EXPECT_EQ(testing::acceleration<double>(cloth, false),
            testing::acceleration<double>(cloth, false));
}

TEST(ReferenceAgreement, ReferenceBuildsEverySpring) {
  for (const auto& shape : kShapes) {
    const reference::ReferenceCloth<double> reference(busy_scene(shape[0], shape[1]));
    EXPECT_EQ(reference.springs().size(), count_springs(shape[0], shape[1]).total());
  }
}

TEST(ReferenceAgreement, SameBitsWithOneOrTwoThreads) {
  const Scene scene = busy_scene(80, 70);  // large enough to run threaded
  PipelineOptions one, two;
  one.threads = 1;
  two.threads = 2;
  Cloth serial(scene, Precision::Float32, one);
  Cloth threaded(scene, Precision::Float32, two);
  EXPECT_EQ(testing::acceleration<float>(serial), testing::acceleration<float>(threaded));
}

}  // namespace
}  // namespace clothlab
