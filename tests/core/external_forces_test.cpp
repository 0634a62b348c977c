// The external-forces extension: plus the springs (a plain loop over the topology) it is
// eval_acceleration, with wind; without wind it is gravity, constant in x; the wind part
// follows the triangle formula over the topology's triangles, turned grid or not, and gives
// the same bits on any thread count. Its revision 2's rows call writes, on its rows alone,
// the bits of the whole-cloth call, in any split into ranges and slots.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include "extension_support.hpp"

namespace clothlab {
namespace {

using testing::host_extension;
using testing::values_of;

template <class Real>
void expect_external_plus_springs_is_the_acceleration(Precision precision, double tolerance) {
  const Scene scene = testing::busy_scene(11, 9);
  Cloth cloth(scene, precision, {});
  const clothlab_system& system = cloth.system();
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 3, 0.05, x, v);
  const auto& external =
      host_extension<clothlab_external_forces_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES);
  EXPECT_EQ(external.depends_on_position(system.context), 1);
  void* a = system.alloc_vector(system.context);
  ASSERT_EQ(external.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
  const std::vector<double> external_part = values_of<Real>(system, a);
  const std::vector<double> springs = testing::spring_acceleration(
      testing::topology_of(system), testing::inverse_masses<Real>(system), x, v);
  const std::vector<double> total = testing::acceleration<Real>(cloth);
  double scale = 0;
  for (double value : total) scale = std::max(scale, std::abs(value));
  for (std::size_t e = 0; e < total.size(); ++e)
    ASSERT_NEAR(external_part[e] + springs[e], total[e], tolerance * scale) << e;
  // The wind is there: the external part is not gravity alone.
  EXPECT_GT(std::abs(external_part[3 * 5 + 2]), 1e-3);
}

TEST(ExternalForces, PlusTheSpringsIsEvalAccelerationFloat64) {
  expect_external_plus_springs_is_the_acceleration<double>(Precision::Float64, 1e-12);
}

TEST(ExternalForces, PlusTheSpringsIsEvalAccelerationFloat32) {
  expect_external_plus_springs_is_the_acceleration<float>(Precision::Float32, 2e-5);
}

TEST(ExternalForces, WithoutWindItIsGravityOnActiveParticlesAndConstant) {
  Scene scene = testing::busy_scene(6, 6);
  scene.wind_strength = 0.0;
  Cloth cloth(scene, Precision::Float64, {});
  const clothlab_system& system = cloth.system();
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 5, 0.2, x, v);
  const auto& external =
      host_extension<clothlab_external_forces_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES);
  EXPECT_EQ(external.depends_on_position(system.context), 0);
  void* a = system.alloc_vector(system.context);
  ASSERT_EQ(external.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
  const std::vector<double> values = values_of<double>(system, a);
  for (uint32_t i = 0; i < system.particle_count; ++i) {
    const bool pinned = std::binary_search(scene.pinned.begin(), scene.pinned.end(), i);
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_EQ(values[3 * i + k], pinned ? 0.0 : scene.gravity[k]) << i;
  }
}

// rows x cols: a grid the pipeline sweeps as it is, or (narrow and tall) turned a quarter.
void expect_wind_follows_the_triangle_formula(uint32_t rows, uint32_t cols) {
  Scene scene = testing::busy_scene(rows, cols);
  scene.gravity = {0, 0, 0};
  Cloth cloth(scene, Precision::Float64, {});
  const clothlab_system& system = cloth.system();
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 9, 0.1, x, v);
  const clothlab_topology topology = testing::topology_of(system);
  const std::vector<double> inverse_mass = testing::inverse_masses<double>(system);
  std::vector<double> expected(x.size(), 0.0);
  for (uint32_t t = 0; t < topology.triangle_count; ++t) {
    const uint32_t* p = topology.triangles + 3 * t;
    double e1[3], e2[3];
    for (std::size_t k = 0; k < 3; ++k) {
      e1[k] = x[3 * p[1] + k] - x[3 * p[0] + k];
      e2[k] = x[3 * p[2] + k] - x[3 * p[0] + k];
    }
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                         e1[0] * e2[1] - e1[1] * e2[0]};
    const double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double area = norm / 2;
    const double facing = (n[0] * scene.wind_direction[0] + n[1] * scene.wind_direction[1] +
                           n[2] * scene.wind_direction[2]) /
                          norm;
    for (std::size_t corner = 0; corner < 3; ++corner)
      for (std::size_t k = 0; k < 3; ++k)
        expected[3 * p[corner] + k] +=
            scene.wind_strength * area * facing * n[k] / norm / 3 * inverse_mass[p[corner]];
  }
  const auto& external =
      host_extension<clothlab_external_forces_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES);
  void* a = system.alloc_vector(system.context);
  ASSERT_EQ(external.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
  const std::vector<double> values = values_of<double>(system, a);
  for (std::size_t e = 0; e < values.size(); ++e) ASSERT_NEAR(values[e], expected[e], 1e-12) << e;
}

TEST(ExternalForces, WindFollowsTheTriangleFormulaOverTheTopologysTriangles) {
  expect_wind_follows_the_triangle_formula(5, 7);
}

TEST(ExternalForces, WindFollowsTheTriangleFormulaOnATurnedGrid) {
  expect_wind_follows_the_triangle_formula(20, 3);
}

// In the last columns of a row (the vector kernels' tail) and in its first.
void expect_a_non_finite_position_is_reported(Precision precision) {
  const Scene scene = testing::busy_scene(6, 37);
  for (const uint32_t particle : {6 * 37 - 2, 2 * 37}) {
    Cloth cloth(scene, precision, {});
    std::vector<double> x, v;
    testing::move_off_rest(cloth, 2, 0.05, x, v);
    x[3 * particle + 2] = std::numeric_limits<double>::infinity();
    cloth.set_state(x, v);
    const clothlab_system& system = cloth.system();
    const auto& external =
        host_extension<clothlab_external_forces_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES);
    void* a = system.alloc_vector(system.context);
    EXPECT_EQ(external.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_ERROR_NUMERICAL)
        << particle;
  }
}

TEST(ExternalForces, NonFinitePositionIsReportedFloat32) {
  expect_a_non_finite_position_is_reported(Precision::Float32);
}

TEST(ExternalForces, NonFinitePositionIsReportedFloat64) {
  expect_a_non_finite_position_is_reported(Precision::Float64);
}

// The threads' blocks start mid-grid, where a block needs the cells of the row above it.
TEST(ExternalForces, SameBitsOnAnyThreadCount) {
  const Scene scene = testing::busy_scene(70, 64);
  ASSERT_GE(std::size_t{scene.rows} * scene.cols, parallel_from_particles);
  std::vector<std::vector<double>> results;
  for (int threads : {1, 2, 3}) {
    Cloth cloth(scene, Precision::Float32, {true, threads});
    const clothlab_system& system = cloth.system();
    std::vector<double> x, v;
    testing::move_off_rest(cloth, 4, 0.05, x, v);
    const auto& external =
        host_extension<clothlab_external_forces_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES);
    void* a = system.alloc_vector(system.context);
    ASSERT_EQ(external.acceleration(system.context, 0.0, system.x, a), CLOTHLAB_OK);
    results.push_back(values_of<float>(system, a));
  }
  EXPECT_EQ(results[0], results[1]);
  EXPECT_EQ(results[0], results[2]);
}

// The rows call over ranges of 1 to 9 rows (the first at row 0, the last at the last row),
// two slots at a time on two threads, into a vector holding a marker elsewhere: each call
// writes its rows' bits of the whole-cloth call and nothing else.
template <class Real>
void expect_rows_calls_are_the_whole_call(Precision precision, bool air) {
  // 37 columns: the lane kernels' tails; enough particles for a thread per slot.
  Scene scene = testing::busy_scene(113, 37);
  if (air) {
    scene.air.density = 1.2;
    scene.air.drag_coefficient = 1.1;
    scene.air.lift_coefficient = 0.4;
  }
  Cloth cloth(scene, precision, {true, 2});
  std::vector<double> x, v;
  testing::move_off_rest(cloth, 7, 0.05, x, v);
  const clothlab_system& system = cloth.system();
  const auto& external =
      host_extension<clothlab_external_forces_2_extension>(system, CLOTHLAB_EXT_EXTERNAL_FORCES_2);
  EXPECT_EQ(external.depends_on_velocity(system.context), air ? 1 : 0);
  void* whole = system.alloc_vector(system.context);
  ASSERT_EQ(external.acceleration(system.context, 0.0, system.x, whole), CLOTHLAB_OK);
  const std::vector<double> expected = values_of<Real>(system, whole);
  constexpr double kMarker = 12345.0;
  void* rows = testing::vector_from<Real>(system, std::vector<double>(expected.size(), kMarker));
  std::vector<std::pair<uint32_t, uint32_t>> ranges;
  for (uint32_t begin = 0, size = 1; begin < scene.rows; begin += size, size = size % 9 + 2)
    ranges.emplace_back(begin, std::min(begin + size, scene.rows));
  const std::size_t row_values = 3 * std::size_t{scene.cols};
  for (std::size_t r = 0; r + 1 < ranges.size(); r += 2) {
    // Before: the two ranges' rows hold the marker, the rows below them their results.
    const std::vector<double> before = values_of<Real>(system, rows);
    for (std::size_t e = 0; e < before.size(); ++e)
      ASSERT_EQ(before[e], e < ranges[r].first * row_values ? expected[e] : kMarker) << e;
    clothlab_status status[2] = {CLOTHLAB_OK, CLOTHLAB_OK};
    std::thread second([&] {
      status[1] = external.acceleration_rows(system.context, 0.0, system.x, rows,
                                             ranges[r + 1].first, ranges[r + 1].second, 1);
    });
    status[0] = external.acceleration_rows(system.context, 0.0, system.x, rows, ranges[r].first,
                                           ranges[r].second, 0);
    second.join();
    ASSERT_EQ(status[0], CLOTHLAB_OK);
    ASSERT_EQ(status[1], CLOTHLAB_OK);
  }
  if (ranges.size() % 2 == 1) {
    ASSERT_EQ(external.acceleration_rows(system.context, 0.0, system.x, rows, ranges.back().first,
                                         ranges.back().second, 0),
              CLOTHLAB_OK);
  }
  EXPECT_EQ(values_of<Real>(system, rows), expected);
  // A range past the last row, a slot past the host's threads.
  EXPECT_EQ(external.acceleration_rows(system.context, 0.0, system.x, rows, 20, scene.rows + 1, 0),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
  EXPECT_EQ(external.acceleration_rows(system.context, 0.0, system.x, rows, 0, 1, 2),
            CLOTHLAB_ERROR_INVALID_ARGUMENT);
}

TEST(ExternalForces, RowsCallsAreTheWholeCallFloat32) {
  expect_rows_calls_are_the_whole_call<float>(Precision::Float32, false);
}

TEST(ExternalForces, RowsCallsAreTheWholeCallFloat64WithAir) {
  expect_rows_calls_are_the_whole_call<double>(Precision::Float64, true);
}

// A grid the pipeline sweeps turned has no cheap range of grid rows: no revision 2 there.
TEST(ExternalForces, RowsCallIsNotOfferedOnATurnedGrid) {
  Cloth cloth(testing::busy_scene(20, 3), Precision::Float32, {});
  const clothlab_system& system = cloth.system();
  EXPECT_NE(system.get_extension(system.context, CLOTHLAB_EXT_EXTERNAL_FORCES), nullptr);
  EXPECT_EQ(system.get_extension(system.context, CLOTHLAB_EXT_EXTERNAL_FORCES_2), nullptr);
}

}  // namespace
}  // namespace clothlab
