// Pinned particles must keep their exact bits through a long run driven by the system
// callbacks, while every other particle moves.
#include <gtest/gtest.h>

#include <cstring>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

template <class Real>
class Pinned : public ::testing::Test {};
using Precisions = ::testing::Types<float, double>;
TYPED_TEST_SUITE(Pinned, Precisions);

TYPED_TEST(Pinned, BitForBitUnchangedAfterThousandSymplecticEulerSteps) {
  Scene scene = testing::bare_scene(5, 4);
  scene.structural = {200.0, 0.5};
  scene.shear = {100.0, 0.2};
  scene.flexion = {50.0, 0.1};
  scene.gravity = {0, -9.81, 0};
  scene.wind_direction = {0.6, 0.0, 0.8};
  scene.wind_strength = 3.0;
  scene.pinned = {0, 3, 9};
  const Precision precision =
      sizeof(TypeParam) == sizeof(float) ? Precision::Float32 : Precision::Float64;
  Cloth cloth(scene, precision, {});
  const clothlab_system& system = cloth.system();
  // Pinned particles start with a non-zero velocity too: it must be left untouched.
  std::vector<double> x, v;
  cloth.positions(x);
  cloth.velocities(v);
  for (uint32_t pinned : scene.pinned) v[3 * pinned] = 0.25;
  cloth.set_state(x, v);
  const std::vector<double> x_start = x;

  auto snapshot = [&](const void* vector, uint32_t i) {
    TypeParam bits[3];
    for (int k = 0; k < 3; ++k)
      bits[k] = static_cast<const TypeParam*>(vector)[k * system.stride + i];
    return std::vector<TypeParam>(bits, bits + 3);
  };
  std::vector<std::vector<TypeParam>> x_before, v_before;
  for (uint32_t pinned : scene.pinned) {
    x_before.push_back(snapshot(system.x, pinned));
    v_before.push_back(snapshot(system.v, pinned));
  }

  void* a = system.alloc_vector(system.context);
  const double dt = 1e-3;
  for (int step = 0; step < 1000; ++step) {
    ASSERT_EQ(system.eval_acceleration(system.context, step * dt, system.x, system.v, a),
              CLOTHLAB_OK);
    system.axpy(system.context, system.v, dt, a);
    system.axpy(system.context, system.x, dt, system.v);
  }

  for (std::size_t p = 0; p < scene.pinned.size(); ++p) {
    const auto x_after = snapshot(system.x, scene.pinned[p]);
    const auto v_after = snapshot(system.v, scene.pinned[p]);
    EXPECT_EQ(std::memcmp(x_after.data(), x_before[p].data(), 3 * sizeof(TypeParam)), 0);
    EXPECT_EQ(std::memcmp(v_after.data(), v_before[p].data(), 3 * sizeof(TypeParam)), 0);
  }
  cloth.positions(x);
  EXPECT_LT(x[3 * 19 + 1], x_start[3 * 19 + 1] - 0.1) << "the free corner should have fallen";
  EXPECT_TRUE(cloth.state_is_finite());
}

}  // namespace
}  // namespace clothlab
