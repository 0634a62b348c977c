// The drape shadow's area against shapes whose area is known: a flat square seen face on and at
// an angle (A cos theta), a square folded onto itself (the union: half), a disc-like fan.
#include <gtest/gtest.h>

#include <clothlab/analysis/projected_area.hpp>
#include <cmath>
#include <vector>

namespace clothlab::analysis {
namespace {

// An n x n grid of a side-1 square in the xz plane, its cells split in two triangles.
struct Grid {
  std::vector<double> positions;
  std::vector<uint32_t> triangles;
};

Grid square(int n) {
  Grid grid;
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      grid.positions.insert(grid.positions.end(), {c / (n - 1.0), 0.0, r / (n - 1.0)});
    }
  for (int r = 0; r + 1 < n; ++r)
    for (int c = 0; c + 1 < n; ++c) {
      const auto at = [n](int row, int col) { return static_cast<uint32_t>(row * n + col); };
      grid.triangles.insert(grid.triangles.end(), {at(r, c), at(r, c + 1), at(r + 1, c)});
      grid.triangles.insert(grid.triangles.end(), {at(r, c + 1), at(r + 1, c + 1), at(r + 1, c)});
    }
  return grid;
}

TEST(ProjectedArea, AFlatSquareSeenFaceOnAndAtAnAngle) {
  const Grid grid = square(11);
  EXPECT_NEAR(projected_area(grid.positions, grid.triangles, {0, 1, 0}), 1.0, 1e-9);
  // Seen along a normal 60 degrees off its own: the shadow is cos 60 = half of it.
  const double angle = 60 * 3.14159265358979323846 / 180;
  EXPECT_NEAR(projected_area(grid.positions, grid.triangles, {std::sin(angle), std::cos(angle), 0}),
              0.5, 4.0 / 512);
}

TEST(ProjectedArea, AFoldedSquareCountsItsOverlapOnce) {
  Grid grid = square(11);
  // The far half (z > 0.5) folded back over the near half, 1 cm above it.
  for (std::size_t i = 0; i < grid.positions.size(); i += 3)
    if (grid.positions[i + 2] > 0.5) {
      grid.positions[i + 2] = 1.0 - grid.positions[i + 2];
      grid.positions[i + 1] = 0.01;
    }
  EXPECT_NEAR(projected_area(grid.positions, grid.triangles, {0, 1, 0}), 0.5, 4.0 / 512);
}

TEST(ProjectedArea, AnEdgeOnSquareHasNoShadow) {
  const Grid grid = square(5);
  EXPECT_EQ(projected_area(grid.positions, grid.triangles, {1, 0, 0}), 0.0);
}

}  // namespace
}  // namespace clothlab::analysis
