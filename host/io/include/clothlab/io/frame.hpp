// One frame of a cloth run as the frame files hold it: float32 per-vertex data of a
// rows x cols grid (particle r * cols + c), triangulated as the core triangulates it.
#pragma once

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

// The grid's vertices and the core's triangles of it (clothlab::grid_triangles).
struct GridMesh {
  GridMesh(uint32_t rows, uint32_t cols);
  uint32_t rows = 0, cols = 0;
  std::vector<uint32_t> triangles;  // vertex indices, 3 per triangle
  uint64_t vertex_count() const { return uint64_t{rows} * cols; }
  uint64_t triangle_count() const { return triangles.size() / 3; }
};

// stretch[i] for every vertex from its positions and the rest lengths of its springs.
void compute_stretch(const GridMesh& mesh, double column_rest, double row_rest,
                     const std::vector<float>& positions, std::vector<float>& stretch);

}  // namespace clothlab::io
