// The drag and lift model of clothlab.air/1 (clothlab/ext/air.h) on one flat grid cell of unit
// side in the xy plane (corners a=(0,0) b=(1,0) c=(0,-1) d=(1,-1), triangles abc and bdc, area
// 1/2 each, normal +z, mass 1 per particle) against hand values, and on busy moving sheets
// against the reference cloth's independent implementation (by angles and unit vectors), through
// every path the engine evaluates it on: eval_acceleration, the external-forces extension.
// (The fused step_rkn is checked against the reference in fused_step_test.cpp's "_air" cases.)
#include <clothlab/ext/external_forces.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "cloth_test_support.hpp"
#include "extension_support.hpp"
#include "reference_forces.hpp"

namespace clothlab {
namespace {

using testing::acceleration;
using testing::bare_scene;

constexpr double kDensity = 1.2;

Scene airy_cell(Vec3 wind, double drag, double lift) {
  Scene scene = bare_scene(2, 2);
  scene.air = {wind, kDensity, drag, lift};
  return scene;
}

// The cell's particles all moving at `velocity`.
void move_all(Cloth& cloth, Vec3 velocity) {
  std::vector<double> x, v;
  cloth.positions(x);
  v.resize(x.size());
  for (std::size_t e = 0; e < v.size(); ++e) v[e] = velocity[e % 3];
  cloth.set_state(x, v);
}

// The total force on the cloth (unit masses: the sum of the accelerations).
Vec3 total(const std::vector<double>& a) {
  Vec3 sum{0, 0, 0};
  for (std::size_t e = 0; e < a.size(); ++e) sum[e % 3] += a[e];
  return sum;
}

TEST(Air, AFlatCellFaceOnFeelsDragAlongTheStreamGrowingWithItsSquare) {
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    for (double speed : {2.0, 4.0}) {
      Cloth cloth(airy_cell({0, 0, speed}, 1.1, 0.7), precision, {});
      const std::vector<double> a = precision == Precision::Float32 ? acceleration<float>(cloth)
                                                                    : acceleration<double>(cloth);
      // Each triangle: density C_d A |v|^2 / 2 along z, no lift (cos sin = 0); a third per
      // corner, and b and c belong to both triangles.
      const double per_triangle = 0.5 * kDensity * 1.1 * 0.5 * speed * speed;
      const double corner_triangles[] = {1, 2, 2, 1};
      for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(a[3 * i + 0], 0.0, 1e-6) << to_string(precision);
        EXPECT_NEAR(a[3 * i + 1], 0.0, 1e-6) << to_string(precision);
        EXPECT_NEAR(a[3 * i + 2], corner_triangles[i] * per_triangle / 3, 1e-6 * speed * speed)
            << to_string(precision) << " speed " << speed;
      }
      EXPECT_EQ(cloth.counters().normals_computed, 2u);
    }
  }
}

// The stream at 30 degrees from the normal, in the xz plane: u = U (sin, 0, cos). Drag
// density C_d A |cos| U^2 / 2 along u; lift density C_l A cos sin U^2 / 2 along (-cos, 0, sin),
// the normal's part perpendicular to u, normalised.
TEST(Air, AnObliqueStreamGivesDragAlongItAndLiftAcrossIt) {
  const double angle = std::numbers::pi / 6, speed = 3.0, s = std::sin(angle), c = std::cos(angle);
  const double q_area = 0.5 * kDensity * speed * speed * 1.0;  // both triangles: area 1
  const Vec3 wind{speed * s, 0, speed * c};
  Cloth drag_only(airy_cell(wind, 1.3, 0.0), Precision::Float64, {});
  Cloth lift_only(airy_cell(wind, 0.0, 0.8), Precision::Float64, {});
  const Vec3 drag = total(acceleration<double>(drag_only));
  const Vec3 lift = total(acceleration<double>(lift_only));
  const Vec3 expected_drag{1.3 * q_area * c * s, 0, 1.3 * q_area * c * c};
  const Vec3 expected_lift{-0.8 * q_area * c * s * c, 0, 0.8 * q_area * c * s * s};
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(drag[k], expected_drag[k], 1e-12) << k;
    EXPECT_NEAR(lift[k], expected_lift[k], 1e-12) << k;
  }
  EXPECT_NEAR(lift[0] * wind[0] + lift[1] * wind[1] + lift[2] * wind[2], 0.0, 1e-12);
}

TEST(Air, TheForcesDoNotDependOnWhichWayTheNormalPoints) {
  const Vec3 wind{1.0, -0.5, 2.0};
  Scene up = airy_cell(wind, 1.0, 1.0);
  Scene down = up;
  down.row_axis = {0, 1, 0};  // rows along +y: the triangles' winding and normal flip
  down.origin = {0, -1, 0};   // the same four points
  Cloth a_up(up, Precision::Float64, {}), a_down(down, Precision::Float64, {});
  const Vec3 force_up = total(acceleration<double>(a_up));
  const Vec3 force_down = total(acceleration<double>(a_down));
  EXPECT_GT(std::hypot(force_up[0], force_up[1], force_up[2]), 1.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(force_up[k], force_down[k], 1e-12) << k;
}

TEST(Air, ACellMovingWithTheWindOrEdgeOnFeelsNothing) {
  const Vec3 wind{1.5, -2.0, 0.75};
  Cloth riding(airy_cell(wind, 1.0, 1.0), Precision::Float64, {});
  move_all(riding, wind);
  // Zero up to the rounding of the corners' mean velocity (|u| ~ 1e-16: forces ~ 1e-32, where
  // the same cell at rest feels ~ 1 N).
  for (double component : acceleration<double>(riding)) EXPECT_NEAR(component, 0.0, 1e-30);
  Cloth edge_on(airy_cell({3.0, -1.0, 0.0}, 1.0, 1.0), Precision::Float64, {});
  for (double component : acceleration<double>(edge_on)) EXPECT_EQ(component, 0.0);
}

TEST(Air, OnlyTheVelocityRelativeToTheAirCounts) {
  const Vec3 wind{1.0, 0.5, 2.0}, velocity{-0.5, 0.25, 0.75};
  Cloth moving(airy_cell(wind, 1.2, 0.9), Precision::Float64, {});
  move_all(moving, velocity);
  Cloth still(
      airy_cell({wind[0] - velocity[0], wind[1] - velocity[1], wind[2] - velocity[2]}, 1.2, 0.9),
      Precision::Float64, {});
  const std::vector<double> a = acceleration<double>(moving), b = acceleration<double>(still);
  for (std::size_t e = 0; e < a.size(); ++e) EXPECT_NEAR(a[e], b[e], 1e-12) << e;
}

TEST(Air, NoAirNoStage) {
  Scene scene = airy_cell({0, 0, 3}, 1.0, 1.0);
  scene.air.density = 0.0;
  Cloth cloth(scene, Precision::Float32, {});
  for (double component : acceleration<float>(cloth)) EXPECT_EQ(component, 0.0);
  EXPECT_EQ(cloth.counters().normals_computed, 0u);
}

Scene airy_busy_scene(uint32_t rows, uint32_t cols, bool wind) {
  Scene scene = testing::busy_scene(rows, cols);
  if (!wind) scene.wind_strength = 0.0;
  scene.air = {{2.5, -0.4, 1.5}, 1.225, 1.2, 0.8};
  return scene;
}

// The moving, perturbed state of reference_agreement_test.cpp.
void move_off_rest(Cloth& cloth, uint32_t seed, std::vector<double>& x, std::vector<double>& v) {
  testing::move_off_rest(cloth, seed, 0.05, x, v);
}

template <class Real>
void expect_agreement_with_the_reference(uint32_t rows, uint32_t cols, bool wind, int threads,
                                         double tolerance) {
  const Scene scene = airy_busy_scene(rows, cols, wind);
  Cloth cloth(scene, sizeof(Real) == 4 ? Precision::Float32 : Precision::Float64, {true, threads});
  std::vector<double> x, v;
  move_off_rest(cloth, rows * 100 + cols, x, v);
  reference::ReferenceCloth<Real> reference(scene);
  std::vector<Real> xr(x.begin(), x.end()), vr(v.begin(), v.end()), ar(x.size()), er(x.size());
  reference.acceleration(xr.data(), vr.data(), ar.data());
  reference.external_acceleration(xr.data(), vr.data(), er.data());

  const clothlab_system& system = cloth.system();
  const std::vector<double> full = acceleration<Real>(cloth);
  const auto& external = testing::host_extension<clothlab_external_forces_extension>(
      system, CLOTHLAB_EXT_EXTERNAL_FORCES);
  EXPECT_EQ(external.depends_on_position(system.context), 1);
  void* a = system.alloc_vector(system.context);
  ASSERT_EQ(external.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
  const std::vector<double> external_part = testing::values_of<Real>(system, a);

  double scale = 0, external_scale = 0;
  for (Real value : ar) scale = std::max(scale, std::abs(double{value}));
  for (Real value : er) external_scale = std::max(external_scale, std::abs(double{value}));
  for (std::size_t e = 0; e < ar.size(); ++e) {
    ASSERT_NEAR(full[e], ar[e], tolerance * scale) << rows << "x" << cols << " element " << e;
    ASSERT_NEAR(external_part[e], er[e], tolerance * external_scale)
        << rows << "x" << cols << " external, element " << e;
  }
}

const uint32_t kShapes[][2] = {{2, 2}, {3, 3}, {5, 4}, {17, 13}, {20, 3}, {80, 70}};

TEST(Air, AgreesWithTheReferenceInFloat64) {
  for (const auto& shape : kShapes)
    for (bool wind : {false, true})
      expect_agreement_with_the_reference<double>(shape[0], shape[1], wind, 1, 1e-12);
}

TEST(Air, AgreesWithTheReferenceInFloat32) {
  for (const auto& shape : kShapes)
    for (bool wind : {false, true})
      expect_agreement_with_the_reference<float>(shape[0], shape[1], wind, 1, 2e-5);
}

TEST(Air, AgreesWithTheReferenceOnThreadedRowBlocks) {
  expect_agreement_with_the_reference<double>(80, 70, true, 2, 1e-12);
  expect_agreement_with_the_reference<float>(80, 70, false, 3, 2e-5);
}

// An integrator without velocity forces passes v = NULL: the air then uses the system's
// current velocities (no spring is damped by them).
TEST(Air, WithoutVelocitiesTheAirUsesTheSystemsCurrentOnes) {
  const Scene scene = airy_busy_scene(9, 11, false);
  Cloth undamped(scene, Precision::Float64, {false, 1});
  std::vector<double> x, v;
  move_off_rest(undamped, 7, x, v);
  Scene without_damping = scene;
  for (SpringFamily* family :
       {&without_damping.structural, &without_damping.shear, &without_damping.flexion})
    family->kd = 0.0;
  Cloth damped(without_damping, Precision::Float64, {true, 1});
  damped.set_state(x, v);
  const std::vector<double> a = acceleration<double>(undamped, false);
  const std::vector<double> b = acceleration<double>(damped, true);
  for (std::size_t e = 0; e < a.size(); ++e) ASSERT_NEAR(a[e], b[e], 1e-12) << e;
  EXPECT_EQ(undamped.counters().springs_damped, 0u);
}

}  // namespace
}  // namespace clothlab
