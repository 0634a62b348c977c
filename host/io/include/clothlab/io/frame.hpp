// One frame of a cloth run as the frame files hold it: float32 per-vertex data of the cloth's
// particles, drawn as the cloth model's triangles.
#pragma once

#include <clothlab/core/cloth_model.hpp>
#include <clothlab/core/collider.hpp>
#include <cstdint>
#include <vector>

namespace clothlab::io {

struct FrameEnergy {
  double kinetic = 0, spring = 0, gravity = 0;
  double total() const { return kinetic + spring + gravity; }
};

struct Frame {
  uint64_t index = 0;             // 0, 1, 2, ... in the sequence
  uint64_t step = 0;              // simulation step it shows (0: the initial state)
  double time = 0;                // simulated seconds
  std::vector<float> positions;   // 3 per vertex
  std::vector<float> velocities;  // 3 per vertex
  // Per vertex: the largest length / rest length of its structural springs.
  std::vector<float> stretch;
  FrameEnergy energy;
  // The scene's colliders (clothlab.colliders/1) at the pose they held over the step that ended
  // at this frame; none for a scene without.
  std::vector<Collider> colliders;
};

// What the frames draw of a cloth model: its particles, its triangles, and its structural
// springs with their rest lengths (what the per-vertex stretch measures).
struct FrameMesh {
  explicit FrameMesh(const ClothModel& model);
  uint64_t vertex_count = 0;
  std::vector<uint32_t> triangles;  // vertex indices, 3 per triangle
  std::vector<uint32_t> spring_first, spring_second;
  std::vector<double> spring_rest_length;
  uint64_t triangle_count() const { return triangles.size() / 3; }
};

// stretch[i] for every vertex: the largest length / rest length of its structural springs
// (0 for a vertex without one).
void compute_stretch(const FrameMesh& mesh, const std::vector<float>& positions,
                     std::vector<float>& stretch);

}  // namespace clothlab::io
