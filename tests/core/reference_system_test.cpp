// The fast core and the seed-style baseline, both behind clothlab_system, integrated the
// same way for many steps, stay together.
#include "reference_system.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

Scene flag_like(uint32_t rows, uint32_t cols) {
  Scene scene = testing::bare_scene(rows, cols);
  scene.total_mass = 0.5;
  scene.structural = {50.0, 0.05};
  scene.shear = {20.0, 0.02};
  scene.flexion = {5.0, 0.01};
  scene.gravity = {0.0, -9.81, 0.0};
  scene.wind_direction = {0.6, 0.0, 0.8};
  scene.wind_strength = 2.0;
  for (uint32_t r = 0; r < rows; ++r) scene.pinned.push_back(r * cols);
  return scene;
}

// Symplectic Euler through the system callbacks only, as an integrator plugin would.
void integrate(const clothlab_system& system, int steps, double dt) {
  void* a = system.alloc_vector(system.context);
  for (int step = 0; step < steps; ++step) {
    ASSERT_EQ(system.eval_acceleration(system.context, step * dt, system.x, system.v, a),
              CLOTHLAB_OK);
    system.axpy(system.context, system.v, dt, a);
    system.axpy(system.context, system.x, dt, system.v);
  }
}

template <class Real>
double largest_difference(uint32_t rows, uint32_t cols) {
  const Scene scene = flag_like(rows, cols);
  const Precision precision =
      sizeof(Real) == sizeof(float) ? Precision::Float32 : Precision::Float64;
  Cloth fast(scene, precision, {});
  reference::ReferenceSystem<Real> baseline(scene, true);
  integrate(fast.system(), 300, 1e-3);
  integrate(baseline.system(), 300, 1e-3);
  EXPECT_EQ(baseline.force_evals(), 300u);
  std::vector<double> x_fast, x_baseline;
  fast.positions(x_fast);
  baseline.positions(x_baseline);
  double difference = 0.0;
  for (std::size_t e = 0; e < x_fast.size(); ++e) {
    difference = std::max(difference, std::abs(x_fast[e] - x_baseline[e]));
  }
  return difference;
}

TEST(ReferenceSystem, TracksTheCoreInFloat64) {
  EXPECT_LT(largest_difference<double>(9, 7), 1e-10);
  EXPECT_LT(largest_difference<double>(1, 6), 1e-10);
}

TEST(ReferenceSystem, TracksTheCoreInFloat32) { EXPECT_LT(largest_difference<float>(9, 7), 1e-3); }

TEST(ReferenceSystem, FreeParticlesMoveAndPinnedOnesDoNot) {
  const Scene scene = flag_like(4, 3);
  reference::ReferenceSystem<double> baseline(scene, false);
  std::vector<double> before, after;
  baseline.positions(before);
  integrate(baseline.system(), 50, 1e-3);
  baseline.positions(after);
  EXPECT_EQ(after[0], before[0]);                  // particle 0 is pinned
  EXPECT_LT(after[3 * 2 + 1], before[3 * 2 + 1]);  // particle 2 falls
}

}  // namespace
}  // namespace clothlab
