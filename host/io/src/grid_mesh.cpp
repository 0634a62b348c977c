#include <algorithm>
#include <clothlab/core/cloth.hpp>
#include <clothlab/io/frame.hpp>
#include <cmath>

namespace clothlab::io {

GridMesh::GridMesh(uint32_t rows_in, uint32_t cols_in)
    : rows(rows_in), cols(cols_in), triangles(grid_triangles(rows_in, cols_in)) {}

void compute_stretch(const GridMesh& mesh, double column_rest, double row_rest,
                     const std::vector<float>& positions, std::vector<float>& stretch) {
  stretch.assign(mesh.vertex_count(), 0.0f);
  const auto ratio = [&](uint64_t i, uint64_t j, double rest) {
    const float dx = positions[3 * j] - positions[3 * i];
    const float dy = positions[3 * j + 1] - positions[3 * i + 1];
    const float dz = positions[3 * j + 2] - positions[3 * i + 2];
    return static_cast<float>(std::sqrt(dx * dx + dy * dy + dz * dz) / rest);
  };
  for (uint32_t r = 0; r < mesh.rows; ++r)
    for (uint32_t c = 0; c < mesh.cols; ++c) {
      const uint64_t i = uint64_t{r} * mesh.cols + c;
      if (c + 1 < mesh.cols && column_rest > 0) {
        const float s = ratio(i, i + 1, column_rest);
        stretch[i] = std::max(stretch[i], s);
        stretch[i + 1] = std::max(stretch[i + 1], s);
      }
      if (r + 1 < mesh.rows && row_rest > 0) {
        const float s = ratio(i, i + mesh.cols, row_rest);
        stretch[i] = std::max(stretch[i], s);
        stretch[i + mesh.cols] = std::max(stretch[i + mesh.cols], s);
      }
    }
}

}  // namespace clothlab::io
