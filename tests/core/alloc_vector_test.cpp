#include <gtest/gtest.h>

#include <cstdint>

#include "cloth_test_support.hpp"

namespace clothlab {
namespace {

TEST(AllocVector, AlignedZeroedAndSizedByStride) {
  for (Precision precision : {Precision::Float32, Precision::Float64}) {
    Cloth cloth(testing::bare_scene(7, 5), precision, {});
    const clothlab_system& system = cloth.system();
    EXPECT_EQ(system.particle_count, 35u);
    EXPECT_EQ(system.stride, 48u);  // 35 rounded up to a multiple of 16
    EXPECT_EQ(reinterpret_cast<uintptr_t>(system.x) % 64, 0u);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(system.v) % 64, 0u);
    EXPECT_EQ(reinterpret_cast<uintptr_t>(system.inverse_mass) % 64, 0u);
    const std::size_t element = precision == Precision::Float32 ? 4 : 8;
    for (int vector = 0; vector < 3; ++vector) {
      void* allocated = system.alloc_vector(system.context);
      ASSERT_NE(allocated, nullptr);
      EXPECT_EQ(reinterpret_cast<uintptr_t>(allocated) % 64, 0u);
      const auto* bytes = static_cast<const unsigned char*>(allocated);
      for (std::size_t b = 0; b < 3 * system.stride * element; ++b) ASSERT_EQ(bytes[b], 0);
    }
  }
}

TEST(AllocVector, SystemDescribesTheCloth) {
  Scene scene = testing::bare_scene(2, 5);
  scene.pinned = {0, 3, 4};
  Cloth cloth(scene, Precision::Float64, {});
  const clothlab_system& system = cloth.system();
  EXPECT_EQ(system.struct_size, sizeof(clothlab_system));
  EXPECT_EQ(system.precision, CLOTHLAB_FLOAT64);
  ASSERT_EQ(system.active_count, 2u);  // runs between pins 0, 3, 4 among 10 particles
  EXPECT_EQ(system.active[0].begin, 1u);
  EXPECT_EQ(system.active[0].end, 3u);
  EXPECT_EQ(system.active[1].begin, 5u);
  EXPECT_EQ(system.active[1].end, 10u);
  const auto* inverse_mass = static_cast<const double*>(system.inverse_mass);
  EXPECT_EQ(inverse_mass[0], 0.0);
  EXPECT_EQ(inverse_mass[1], 1.0);  // 10 kg over 10 particles
  EXPECT_EQ(inverse_mass[4], 0.0);
  EXPECT_EQ(cloth.particle_count(), 10u);
  EXPECT_STREQ(to_string(cloth.precision()), "float64");
  EXPECT_STREQ(to_string(Precision::Float32), "float32");
}

TEST(AllocVector, InitialLayoutFollowsTheAxes) {
  Scene scene = testing::bare_scene(3, 2);
  scene.width = 2.0;
  scene.height = 4.0;
  scene.origin = {1, 2, 3};
  scene.col_axis = {0, 0, 1};
  scene.row_axis = {1, 0, 0};
  Cloth cloth(scene, Precision::Float64, {});
  std::vector<double> x;
  cloth.positions(x);
  // Particle (r, c) = index 2r + c sits at origin + 2c z + 2r x.
  const double expected[6][3] = {{1, 2, 3}, {1, 2, 5}, {3, 2, 3}, {3, 2, 5}, {5, 2, 3}, {5, 2, 5}};
  for (int i = 0; i < 6; ++i) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(x[3 * i + k], expected[i][k]) << i << "," << k;
  }
}

}  // namespace
}  // namespace clothlab
