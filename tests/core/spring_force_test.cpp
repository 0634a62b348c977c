// One spring between the two particles of a 2x1 grid (rest length 1, mass 1 each),
// stretched along (0.6, -0.8, 0) to length 2. Hand values: Hooke pulls particle 0 by
// ks * (2 - 1) * (0.6, -0.8, 0); damping adds kd * ((v1 - v0) . d) d.
#include <gtest/gtest.h>

#include <limits>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

using testing::acceleration;
using testing::bare_scene;

template <class Real>
class SpringForce : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(SpringForce, Precisions);

constexpr Precision precision_of(float) { return Precision::Float32; }
constexpr Precision precision_of(double) { return Precision::Float64; }

// x1 - x0 = 2 * (0.6, -0.8, 0); particle 1 moves with velocity (1, 0, 0).
void stretch(Cloth& cloth) { cloth.set_state({0, 0, 0, 1.2, -1.6, 0}, {0, 0, 0, 1, 0, 0}); }

double tolerance_for(Precision precision) { return precision == Precision::Float32 ? 1e-5 : 1e-12; }

TYPED_TEST(SpringForce, HookePullsBothEndsTogether) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {10.0, 0.0};
  const Precision precision = precision_of(TypeParam{});
  Cloth cloth(scene, precision, {});
  stretch(cloth);
  const std::vector<double> a = acceleration<TypeParam>(cloth);
  const double tolerance = 10 * tolerance_for(precision);
  // |F| = 10 N/m * 1 m along the unit direction (0.6, -0.8, 0), mass 1 kg.
  EXPECT_NEAR(a[0], 6.0, tolerance);
  EXPECT_NEAR(a[1], -8.0, tolerance);
  EXPECT_NEAR(a[2], 0.0, tolerance);
  EXPECT_NEAR(a[3], -6.0, tolerance);
  EXPECT_NEAR(a[4], 8.0, tolerance);
  EXPECT_NEAR(a[5], 0.0, tolerance);
  EXPECT_EQ(cloth.counters().springs_evaluated, 1u);
  EXPECT_EQ(cloth.counters().springs_damped, 0u);  // kd = 0: no damping stage
}

TYPED_TEST(SpringForce, CompressedSpringPushesApart) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {10.0, 0.0};
  Cloth cloth(scene, precision_of(TypeParam{}), {});
  cloth.set_state({0, 0, 0, 0, -0.25, 0}, {0, 0, 0, 0, 0, 0});
  const std::vector<double> a = acceleration<TypeParam>(cloth);
  // 10 N/m * 0.75 m compression: particle 0 pushed up (+y), particle 1 down.
  EXPECT_NEAR(a[1], 7.5, 1e-5);
  EXPECT_NEAR(a[4], -7.5, 1e-5);
}

TYPED_TEST(SpringForce, DampingOpposesRelativeVelocityAlongTheSpring) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {0.0, 5.0};
  const Precision precision = precision_of(TypeParam{});
  Cloth cloth(scene, precision, {});
  stretch(cloth);
  const std::vector<double> a = acceleration<TypeParam>(cloth);
  const double tolerance = 10 * tolerance_for(precision);
  // (v1 - v0) . d = 0.6 m/s; F0 = 5 * 0.6 * (0.6, -0.8, 0) = (1.8, -2.4, 0).
  EXPECT_NEAR(a[0], 1.8, tolerance);
  EXPECT_NEAR(a[1], -2.4, tolerance);
  EXPECT_NEAR(a[2], 0.0, tolerance);
  EXPECT_NEAR(a[3], -1.8, tolerance);
  EXPECT_NEAR(a[4], 2.4, tolerance);
  EXPECT_NEAR(a[5], 0.0, tolerance);
  EXPECT_EQ(cloth.counters().springs_damped, 1u);
}

TYPED_TEST(SpringForce, HookeAndDampingAdd) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {10.0, 5.0};
  Cloth cloth(scene, precision_of(TypeParam{}), {});
  stretch(cloth);
  const std::vector<double> a = acceleration<TypeParam>(cloth);
  EXPECT_NEAR(a[0], 6.0 + 1.8, 1e-4);
  EXPECT_NEAR(a[1], -8.0 - 2.4, 1e-4);
}

TYPED_TEST(SpringForce, NoDampingWithoutVelocityForces) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {10.0, 5.0};
  PipelineOptions options;
  options.velocity_forces = false;
  Cloth cloth(scene, precision_of(TypeParam{}), options);
  stretch(cloth);
  const std::vector<double> a = acceleration<TypeParam>(cloth, /*with_velocity=*/false);
  EXPECT_NEAR(a[0], 6.0, 1e-4);  // Hooke only
  EXPECT_NEAR(a[1], -8.0, 1e-4);
  EXPECT_EQ(cloth.counters().springs_evaluated, 1u);
  EXPECT_EQ(cloth.counters().springs_damped, 0u);
}

TYPED_TEST(SpringForce, PureDampingFamilyIsDroppedWithoutVelocityForces) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {0.0, 5.0};
  PipelineOptions options;
  options.velocity_forces = false;
  Cloth cloth(scene, precision_of(TypeParam{}), options);
  stretch(cloth);
  const std::vector<double> a = acceleration<TypeParam>(cloth, /*with_velocity=*/false);
  for (double component : a) EXPECT_EQ(component, 0.0);
  EXPECT_EQ(cloth.counters().springs_evaluated, 0u);
}

TYPED_TEST(SpringForce, GravityAcceleratesFreeParticlesOnly) {
  Scene scene = bare_scene(2, 1);
  scene.gravity = {0.5, -9.81, 2.0};
  scene.pinned = {0};
  Cloth cloth(scene, precision_of(TypeParam{}), {});
  const std::vector<double> a = acceleration<TypeParam>(cloth);
  EXPECT_EQ(a[0], 0.0);
  EXPECT_EQ(a[1], 0.0);
  EXPECT_EQ(a[2], 0.0);
  EXPECT_NEAR(a[3], 0.5, 1e-6);
  EXPECT_NEAR(a[4], -9.81, 1e-6);
  EXPECT_NEAR(a[5], 2.0, 1e-6);
}

TYPED_TEST(SpringForce, NonFiniteStateIsReported) {
  Scene scene = bare_scene(2, 1);
  scene.structural = {10.0, 0.0};
  Cloth cloth(scene, precision_of(TypeParam{}), {});
  cloth.set_state({0, 0, 0, 0, std::numeric_limits<double>::infinity(), 0}, {0, 0, 0, 0, 0, 0});
  const clothlab_system& system = cloth.system();
  void* a = system.alloc_vector(system.context);
  EXPECT_EQ(system.eval_acceleration(system.context, 0.0, system.x, system.v, a),
            CLOTHLAB_ERROR_NUMERICAL);
  EXPECT_FALSE(cloth.state_is_finite());
}

}  // namespace
}  // namespace clothlab
