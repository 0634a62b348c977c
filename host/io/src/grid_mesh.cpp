#include <algorithm>
#include <clothlab/io/frame.hpp>
#include <cmath>

namespace clothlab::io {

std::vector<int32_t> GridMesh::triangles() const {
  std::vector<int32_t> indices;
  indices.reserve(3 * triangle_count());
  for (uint32_t r = 0; r + 1 < rows; ++r)
    for (uint32_t c = 0; c + 1 < cols; ++c) {
      const auto a = static_cast<int32_t>(r * cols + c);
      const auto b = a + 1;
      const auto d = a + static_cast<int32_t>(cols);
      indices.insert(indices.end(), {a, d, b, b, d, d + 1});
    }
  return indices;
}

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
