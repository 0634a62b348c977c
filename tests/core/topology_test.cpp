// The topology extension on the grid: spring counts per family against the seed's formula,
// the springs' ends, rest lengths and laws, the adjacency, both colourings (independent,
// covering, 12 and 5 colours), the triangles, and the grid extension's stencils for the
// colours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "extension_support.hpp"

namespace clothlab {
namespace {

using testing::busy_scene;
using testing::topology_of;

uint64_t family_count(const clothlab_topology& t, uint8_t family) {
  return static_cast<uint64_t>(std::count(t.family, t.family + t.spring_count, family));
}

TEST(Topology, SpringCountsPerFamilyMatchTheSeedFormula) {
  const uint32_t shapes[][2] = {{2, 2}, {2, 3}, {3, 2}, {5, 4}, {17, 13}, {50, 50}};
  for (const auto& shape : shapes) {
    Cloth cloth(busy_scene(shape[0], shape[1]), Precision::Float64, {});
    const clothlab_topology t = topology_of(cloth.system());
    const SpringCounts seed = testing::seed_equation_2_2(shape[0], shape[1]);
    EXPECT_EQ(family_count(t, CLOTHLAB_SPRING_STRUCTURAL), seed.structural) << shape[0];
    EXPECT_EQ(family_count(t, CLOTHLAB_SPRING_SHEAR), seed.shear) << shape[0];
    EXPECT_EQ(family_count(t, CLOTHLAB_SPRING_FLEXION), seed.flexion) << shape[0];
    EXPECT_EQ(t.spring_count, seed.total());
    EXPECT_EQ(t.particle_count, shape[0] * shape[1]);
  }
}

TEST(Topology, AFamilyWithoutStiffnessOrDampingIsLeftOut) {
  Scene scene = busy_scene(6, 5);
  scene.shear = {0.0, 0.0};
  Cloth cloth(scene, Precision::Float32, {});
  const clothlab_topology t = topology_of(cloth.system());
  EXPECT_EQ(family_count(t, CLOTHLAB_SPRING_SHEAR), 0u);
  EXPECT_EQ(t.spring_count, count_springs(6, 5).total() - count_springs(6, 5).shear);
}

TEST(Topology, SpringsJoinLowerToHigherIndexWithTheirFamilysLawAndInitialLength) {
  const Scene scene = busy_scene(7, 6);
  Cloth cloth(scene, Precision::Float64, {});
  const clothlab_topology t = topology_of(cloth.system());
  std::vector<double> x;
  cloth.positions(x);
  std::set<std::pair<uint32_t, uint32_t>> pairs;
  for (uint32_t s = 0; s < t.spring_count; ++s) {
    ASSERT_LT(t.first[s], t.second[s]);
    EXPECT_TRUE(pairs.insert({t.first[s], t.second[s]}).second) << "spring " << s << " twice";
    const SpringFamily& law = t.family[s] == CLOTHLAB_SPRING_STRUCTURAL ? scene.structural
                              : t.family[s] == CLOTHLAB_SPRING_SHEAR    ? scene.shear
                                                                        : scene.flexion;
    EXPECT_EQ(t.ks[s], law.ks);
    EXPECT_EQ(t.kd[s], law.kd);
    double squared = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double d = x[3 * t.second[s] + k] - x[3 * t.first[s] + k];
      squared += d * d;
    }
    EXPECT_NEAR(t.rest_length[s], std::sqrt(squared), 1e-12);
  }
}

TEST(Topology, AdjacencyListsEachSpringAtBothEndsAscending) {
  Cloth cloth(busy_scene(8, 9), Precision::Float64, {});
  const clothlab_topology t = topology_of(cloth.system());
  ASSERT_EQ(t.adjacency_offsets[0], 0u);
  ASSERT_EQ(t.adjacency_offsets[t.particle_count], 2 * t.spring_count);
  std::vector<int> seen(t.spring_count, 0);
  for (uint32_t i = 0; i < t.particle_count; ++i) {
    for (uint32_t e = t.adjacency_offsets[i]; e < t.adjacency_offsets[i + 1]; ++e) {
      const uint32_t s = t.adjacent_springs[e];
      EXPECT_TRUE(t.first[s] == i || t.second[s] == i);
      if (e > t.adjacency_offsets[i]) {
        EXPECT_LT(t.adjacent_springs[e - 1], s);
      }
      ++seen[s];
    }
  }
  for (int count : seen) EXPECT_EQ(count, 2);
}

TEST(Topology, TwelveSpringColoursOfIndependentSpringsCoverEverySpringOnce) {
  Cloth cloth(busy_scene(9, 11), Precision::Float64, {});
  const clothlab_topology t = topology_of(cloth.system());
  ASSERT_EQ(t.spring_color_count, 12u);
  ASSERT_EQ(t.spring_color_offsets[12], t.spring_count);
  std::vector<int> seen(t.spring_count, 0);
  for (uint32_t c = 0; c < t.spring_color_count; ++c) {
    std::set<uint32_t> touched;
    EXPECT_LT(t.spring_color_offsets[c], t.spring_color_offsets[c + 1]) << "colour " << c;
    for (uint32_t m = t.spring_color_offsets[c]; m < t.spring_color_offsets[c + 1]; ++m) {
      const uint32_t s = t.spring_color_members[m];
      if (m > t.spring_color_offsets[c]) {
        EXPECT_LT(t.spring_color_members[m - 1], s);
      }
      EXPECT_TRUE(touched.insert(t.first[s]).second) << "colour " << c << " shares a particle";
      EXPECT_TRUE(touched.insert(t.second[s]).second) << "colour " << c << " shares a particle";
      ++seen[s];
    }
  }
  for (int count : seen) EXPECT_EQ(count, 1);
}

TEST(Topology, FiveParticleColoursRowPlusTwoColumnsAreIndependent) {
  const uint32_t rows = 9, cols = 11;
  Cloth cloth(busy_scene(rows, cols), Precision::Float64, {});
  const clothlab_topology t = topology_of(cloth.system());
  ASSERT_EQ(t.particle_color_count, 5u);
  ASSERT_EQ(t.particle_color_offsets[5], t.particle_count);
  std::vector<uint32_t> color(t.particle_count, 99);
  for (uint32_t c = 0; c < 5; ++c) {
    for (uint32_t m = t.particle_color_offsets[c]; m < t.particle_color_offsets[c + 1]; ++m) {
      const uint32_t i = t.particle_color_members[m];
      EXPECT_EQ(color[i], 99u) << "particle " << i << " in two colours";
      color[i] = c;
      EXPECT_EQ(c, (i / cols + 2 * (i % cols)) % 5);
    }
  }
  for (uint32_t s = 0; s < t.spring_count; ++s)
    EXPECT_NE(color[t.first[s]], color[t.second[s]]) << "spring " << s << " within a colour";
}

TEST(Topology, TwoTrianglesPerCellFacingTheSameWay) {
  const uint32_t rows = 4, cols = 5;
  Cloth cloth(busy_scene(rows, cols), Precision::Float64, {});
  const clothlab_topology t = topology_of(cloth.system());
  ASSERT_EQ(t.triangle_count, 2 * (rows - 1) * (cols - 1));
  std::vector<double> x;
  cloth.positions(x);
  const auto normal = [&](uint32_t triangle) {
    const uint32_t* p = t.triangles + 3 * triangle;
    double e1[3], e2[3];
    for (std::size_t k = 0; k < 3; ++k) {
      e1[k] = x[3 * p[1] + k] - x[3 * p[0] + k];
      e2[k] = x[3 * p[2] + k] - x[3 * p[0] + k];
    }
    return std::array<double, 3>{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                                 e1[0] * e2[1] - e1[1] * e2[0]};
  };
  const std::array<double, 3> first = normal(0);
  for (uint32_t triangle = 0; triangle < t.triangle_count; ++triangle) {
    const std::array<double, 3> n = normal(triangle);
    EXPECT_GT(n[0] * first[0] + n[1] * first[1] + n[2] * first[2], 0.0) << triangle;
  }
}

// clothlab.grid/1: the scene's rows, cols and spacings, and every spring of colour c starts
// where colour c's stencil and parity say and joins the stencil's partner; and the count of
// such starts is the colour's size, so the colour is all of them.
TEST(Topology, TheGridDescribesEachColourAsAStencilAtAParity) {
  const Scene scene = busy_scene(9, 7);
  Cloth cloth(scene, Precision::Float64, {});
  const clothlab_topology t = topology_of(cloth.system());
  const clothlab_grid grid = testing::grid_of(cloth.system());
  EXPECT_EQ(grid.rows, 9u);
  EXPECT_EQ(grid.cols, 7u);
  EXPECT_EQ(grid.column_spacing, scene.width / 6);
  EXPECT_EQ(grid.row_spacing, scene.height / 8);
  ASSERT_EQ(grid.spring_color_count, t.spring_color_count);
  ASSERT_NE(grid.spring_colors, nullptr);
  for (uint32_t c = 0; c < t.spring_color_count; ++c) {
    const clothlab_grid_color& stencil = grid.spring_colors[c];
    const auto starts_here = [&](uint32_t r, uint32_t col) {
      if (r >= stencil.row_end || col < stencil.col_begin || col >= stencil.col_end) return false;
      const bool in_row = stencil.row_step == 0;
      const uint32_t along = in_row ? col : r;
      const uint32_t step = in_row ? static_cast<uint32_t>(stencil.col_step) : stencil.row_step;
      return (along / step) % 2 == stencil.parity;
    };
    uint32_t starts = 0;
    for (uint32_t r = 0; r < grid.rows; ++r)
      for (uint32_t col = 0; col < grid.cols; ++col) starts += starts_here(r, col);
    const uint32_t begin = t.spring_color_offsets[c], end = t.spring_color_offsets[c + 1];
    EXPECT_EQ(end - begin, starts) << "colour " << c;
    for (uint32_t m = begin; m < end; ++m) {
      const uint32_t k = t.spring_color_members[m];
      const uint32_t r = t.first[k] / grid.cols, col = t.first[k] % grid.cols;
      EXPECT_TRUE(starts_here(r, col)) << "colour " << c << " spring " << k;
      EXPECT_EQ(int64_t{t.second[k]} - t.first[k],
                int64_t{stencil.row_step} * grid.cols + stencil.col_step)
          << "colour " << c << " spring " << k;
      EXPECT_EQ(t.rest_length[k], t.rest_length[t.spring_color_members[begin]]);
    }
  }
}

TEST(Topology, EveryCallReturnsTheSameArrays) {
  Cloth cloth(busy_scene(5, 5), Precision::Float32, {});
  const clothlab_topology a = topology_of(cloth.system());
  const clothlab_topology b = topology_of(cloth.system());
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.adjacent_springs, b.adjacent_springs);
  EXPECT_EQ(a.particle_color_members, b.particle_color_members);
}

TEST(HostExtensions, AnUnknownIdOrRevisionIsNull) {
  Cloth cloth(busy_scene(3, 3), Precision::Float64, {});
  const clothlab_system& system = cloth.system();
  ASSERT_TRUE(CLOTHLAB_HAS_FIELD(&system, clothlab_system, get_extension));
  for (const char* id : {"clothlab.jacobian/2", "clothlab.jacobian", "clothlab.topology/0", "",
                         "CLOTHLAB.TOPOLOGY/1", "clothlab.no-such/1"}) {
    EXPECT_EQ(system.get_extension(system.context, id), nullptr) << id;
  }
  EXPECT_EQ(system.get_extension(system.context, nullptr), nullptr);
  for (const char* id : {CLOTHLAB_EXT_TOPOLOGY, CLOTHLAB_EXT_JACOBIAN, CLOTHLAB_EXT_REDUCTIONS,
                         CLOTHLAB_EXT_EXTERNAL_FORCES}) {
    EXPECT_NE(system.get_extension(system.context, id), nullptr) << id;
  }
}

}  // namespace
}  // namespace clothlab
