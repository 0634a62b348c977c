// The cloth mesh as the scenario holds it: positions, one winding of triangles, and the vertex
// colours a pin rule may select by.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace clothlab::builtin {

struct TriangleMesh {
  std::vector<std::array<double, 3>> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
  // One RGB per vertex, or empty when the file has no vertex colours.
  std::vector<std::array<double, 3>> colours;
};

}  // namespace clothlab::builtin
