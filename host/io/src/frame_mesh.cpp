#include <algorithm>
#include <clothlab/io/frame.hpp>
#include <cmath>

namespace clothlab::io {

FrameMesh::FrameMesh(const ClothModel& model)
    : vertex_count(model.particle_count), triangles(model.triangles) {
  for (std::size_t s = 0; s < model.spring_count(); ++s) {
    if (model.family[s] != CLOTHLAB_SPRING_STRUCTURAL || !(model.rest_length[s] > 0)) continue;
    spring_first.push_back(model.first[s]);
    spring_second.push_back(model.second[s]);
    spring_rest_length.push_back(model.rest_length[s]);
  }
}

void compute_stretch(const FrameMesh& mesh, const std::vector<float>& positions,
                     std::vector<float>& stretch) {
  stretch.assign(mesh.vertex_count, 0.0f);
  for (std::size_t s = 0; s < mesh.spring_first.size(); ++s) {
    const uint64_t i = mesh.spring_first[s], j = mesh.spring_second[s];
    const float dx = positions[3 * j] - positions[3 * i];
    const float dy = positions[3 * j + 1] - positions[3 * i + 1];
    const float dz = positions[3 * j + 2] - positions[3 * i + 2];
    const auto ratio =
        static_cast<float>(std::sqrt(dx * dx + dy * dy + dz * dz) / mesh.spring_rest_length[s]);
    stretch[i] = std::max(stretch[i], ratio);
    stretch[j] = std::max(stretch[j], ratio);
  }
}

}  // namespace clothlab::io
