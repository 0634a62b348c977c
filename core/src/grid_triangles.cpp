#include <clothlab/core/cloth.hpp>

namespace clothlab {

std::vector<uint32_t> grid_triangles(uint32_t rows, uint32_t cols) {
  std::vector<uint32_t> triangles;
  if (rows < 2 || cols < 2) return triangles;
  triangles.reserve(6 * std::size_t{rows - 1} * (cols - 1));
  for (uint32_t c = 0; c + 1 < cols; ++c)
    for (uint32_t r = 0; r + 1 < rows; ++r) {
      const uint32_t a = r * cols + c, b = a + 1, below = a + cols, d = below + 1;
      triangles.insert(triangles.end(), {a, b, below, b, d, below});  // as the wind kernel
    }
  return triangles;
}

}  // namespace clothlab
