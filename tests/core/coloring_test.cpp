// Colourings of any mesh: every spring (particle) in exactly one colour, no two springs of a
// colour sharing a particle (no spring joining two particles of a colour), the same colours on
// every build; the checks themselves catch a broken colouring. The counts on a disc and an
// irregular sheet are printed for docs/reference/cloth-model.md.
#include <gtest/gtest.h>

#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/coloring.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cstdio>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cloth_test_support.hpp"
#include "mesh_test_support.hpp"

namespace clothlab {
namespace {

// "" when `coloring` partitions `items` and no two members of a colour are joined (`joined`
// lists, per item, the items it may not share a colour with); else what is wrong.
template <class Joined>
std::string coloring_fault(const Coloring& coloring, std::size_t items, Joined&& joined) {
  std::vector<uint32_t> color_of(items, ~0u);
  for (uint32_t c = 0; c < coloring.count(); ++c)
    for (uint32_t item : coloring.color(c)) {
      if (item >= items) return "item " + std::to_string(item) + " out of range";
      if (color_of[item] != ~0u) return "item " + std::to_string(item) + " in two colours";
      color_of[item] = c;
    }
  for (std::size_t item = 0; item < items; ++item) {
    if (color_of[item] == ~0u) return "item " + std::to_string(item) + " in no colour";
    for (uint32_t other : joined(item))
      if (other != item && color_of[other] == color_of[item])
        return "items " + std::to_string(item) + " and " + std::to_string(other) +
               " share colour " + std::to_string(color_of[item]);
  }
  return {};
}

std::string spring_coloring_fault(const ClothModel& m, const Coloring& coloring) {
  return coloring_fault(coloring, m.spring_count(), [&](std::size_t s) {
    std::vector<uint32_t> touching;
    for (uint32_t end : {m.first[s], m.second[s]})
      for (uint32_t e = m.adjacency_offsets[end]; e < m.adjacency_offsets[end + 1]; ++e)
        touching.push_back(m.adjacent_springs[e]);
    return touching;
  });
}

std::string particle_coloring_fault(const ClothModel& m, const Coloring& coloring) {
  return coloring_fault(coloring, m.particle_count, [&](std::size_t i) {
    std::vector<uint32_t> partners;
    for (uint32_t e = m.adjacency_offsets[i]; e < m.adjacency_offsets[i + 1]; ++e) {
      const uint32_t s = m.adjacent_springs[e];
      partners.push_back(m.first[s] == i ? m.second[s] : m.first[s]);
    }
    return partners;
  });
}

void expect_valid_colorings(const ClothModel& model, const char* name) {
  EXPECT_EQ(spring_coloring_fault(model, model.spring_colors), "") << name;
  EXPECT_EQ(particle_coloring_fault(model, model.particle_colors), "") << name;
  std::printf("%s: %u particles, %zu springs: %u spring colours, %u particle colours\n", name,
              model.particle_count, model.spring_count(), model.spring_colors.count(),
              model.particle_colors.count());
}

TEST(Coloring, DiscAndIrregularMeshAreColouredValidly) {
  const Scene scene = testing::busy_scene(2, 2);
  expect_valid_colorings(*build_mesh_model(testing::disc_mesh(25, 0.02), scene), "disc");
  expect_valid_colorings(*build_mesh_model(testing::irregular_mesh(40, 40), scene),
                         "irregular sheet");
  expect_valid_colorings(
      *build_mesh_model(testing::grid_mesh(testing::busy_scene(30, 30), testing::Diagonals::Rising),
                        scene),
      "grid as triangles");
}

TEST(Coloring, GridKeepsItsFixedColours) {
  const auto model = build_grid_model(testing::busy_scene(9, 7));
  EXPECT_EQ(model->spring_colors.count(), 12u);
  EXPECT_EQ(model->particle_colors.count(), 5u);
  expect_valid_colorings(*model, "grid 9x7");
}

// The grid read as a mesh gets the grid's 12 stencil colours (each the springs of one stencil
// at one parity along it), so xpbd's lane blocks load their ends in order or as split runs
// (plugins/integrators/xpbd_color_blocks.hpp) rather than gather them.
TEST(Coloring, GridReadAsAMeshGetsTheGridsStencilColours) {
  const Scene scene = testing::busy_scene(13, 15);
  const auto mesh = build_mesh_model(testing::grid_mesh(scene, testing::Diagonals::Rising), scene);
  const auto grid = build_grid_model(scene);
  EXPECT_EQ(spring_coloring_fault(*mesh, mesh->spring_colors), "");
  const auto pairs = [](const ClothModel& m, uint32_t c) {
    std::set<std::pair<uint32_t, uint32_t>> out;
    for (uint32_t s : m.spring_colors.color(c)) out.insert({m.first[s], m.second[s]});
    return out;
  };
  std::set<std::set<std::pair<uint32_t, uint32_t>>> grid_colours;
  for (uint32_t c = 0; c < grid->spring_colors.count(); ++c) grid_colours.insert(pairs(*grid, c));
  ASSERT_EQ(mesh->spring_colors.count(), grid->spring_colors.count());
  for (uint32_t c = 0; c < mesh->spring_colors.count(); ++c)
    EXPECT_EQ(grid_colours.count(pairs(*mesh, c)), 1u) << "colour " << c << " is no grid colour";
}

TEST(Coloring, IsTheSameOnEveryBuild) {
  const Scene scene = testing::busy_scene(2, 2);
  const auto once = build_mesh_model(testing::irregular_mesh(15, 17), scene);
  const auto again = build_mesh_model(testing::irregular_mesh(15, 17), scene);
  EXPECT_EQ(once->spring_colors.offsets, again->spring_colors.offsets);
  EXPECT_EQ(once->spring_colors.members, again->spring_colors.members);
  EXPECT_EQ(once->particle_colors.members, again->particle_colors.members);
}

TEST(Coloring, ChecksCatchABrokenColouring) {
  const auto model = build_mesh_model(testing::disc_mesh(3, 0.1), testing::busy_scene(2, 2));
  // Every spring in one colour; every particle in one colour; a particle left out.
  Coloring merged = group_by_color(std::vector<uint32_t>(model->spring_count(), 0), 1);
  EXPECT_NE(spring_coloring_fault(*model, merged), "");
  Coloring one_particle_color = group_by_color(std::vector<uint32_t>(model->particle_count, 0), 1);
  EXPECT_NE(particle_coloring_fault(*model, one_particle_color), "");
  Coloring missing = model->particle_colors;
  missing.members.pop_back();
  --missing.offsets.back();
  EXPECT_NE(particle_coloring_fault(*model, missing), "");
}

TEST(Coloring, GreedyTakesTheSmallestFreeColour) {
  // A path 0-1-2-3: springs alternate two colours, particles two colours.
  const std::vector<uint32_t> first{0, 1, 2}, second{1, 2, 3};
  const std::vector<uint32_t> offsets{0, 1, 3, 5, 6}, adjacent{0, 0, 1, 1, 2, 2};
  const Coloring springs = color_springs(first, second, offsets, adjacent);
  ASSERT_EQ(springs.count(), 2u);
  EXPECT_EQ(std::vector<uint32_t>(springs.color(0).begin(), springs.color(0).end()),
            (std::vector<uint32_t>{0, 2}));
  const Coloring particles = color_particles(first, second, offsets, adjacent);
  ASSERT_EQ(particles.count(), 2u);
  EXPECT_EQ(std::vector<uint32_t>(particles.color(1).begin(), particles.color(1).end()),
            (std::vector<uint32_t>{1, 3}));
}

}  // namespace
}  // namespace clothlab
