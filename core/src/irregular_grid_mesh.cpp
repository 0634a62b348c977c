// A grid scene's sheet as an irregular triangle mesh (triangle_mesh.hpp).
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>

namespace clothlab {
namespace {

uint32_t hash(uint32_t value) {
  value ^= value >> 16;
  value *= 0x7feb352dU;
  value ^= value >> 15;
  value *= 0x846ca68bU;
  return value ^ (value >> 16);
}

// In [-1/4, 1/4): a vertex moves less than half a spacing, so no triangle folds over.
double jitter(uint32_t vertex, uint32_t axis) {
  return (static_cast<double>(hash(3 * vertex + axis) % 1000) / 1000.0 - 0.5) * 0.5;
}

}  // namespace

TriangleMesh irregular_grid_mesh(const Scene& scene) {
  const uint32_t rows = scene.rows, cols = scene.cols;
  const double col_spacing = scene.column_spacing(), row_spacing = scene.row_spacing();
  const Vec3& u = scene.col_axis;
  const Vec3& w = scene.row_axis;
  const Vec3 normal{w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2],
                    w[0] * u[1] - w[1] * u[0]};
  const double normal_spacing = 0.2 * std::sqrt(col_spacing * row_spacing);
  TriangleMesh mesh;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < cols; ++c) {
      const uint32_t i = r * cols + c;
      const double along_cols = (c + jitter(i, 0)) * col_spacing;
      const double along_rows = (r + jitter(i, 1)) * row_spacing;
      const double off_plane = jitter(i, 2) * normal_spacing;
      for (int k = 0; k < 3; ++k)
        mesh.positions.push_back(scene.origin[k] + along_cols * u[k] + along_rows * w[k] +
                                 off_plane * normal[k]);
    }
  for (uint32_t r = 0; r + 1 < rows; ++r)
    for (uint32_t c = 0; c + 1 < cols; ++c) {
      const uint32_t a = r * cols + c, b = a + 1, below = a + cols, d = below + 1;
      if (hash(a + 7919) % 2 == 0)
        mesh.triangles.insert(mesh.triangles.end(), {a, b, d, a, d, below});
      else
        mesh.triangles.insert(mesh.triangles.end(), {a, below, b, b, below, d});
    }
  return mesh;
}

}  // namespace clothlab
