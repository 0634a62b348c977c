// The rules that pick a mesh's pinned vertices: a box, a plane band, a list of indices, a
// vertex colour. The pinned set is the union of the rules in use.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "triangle_mesh.hpp"

namespace clothlab::builtin {

struct BoxRule {
  std::array<double, 3> min, max;  // metres, placed coordinates; inclusive
};

struct PlaneRule {
  std::array<double, 3> point, normal;  // placed coordinates; normal non-zero
  double distance;                      // metres; a vertex within it of the plane is pinned
};

struct ColourRule {
  std::array<double, 3> colour;  // RGB in [0, 1]
  double tolerance;              // largest difference per channel
};

struct PinRules {
  std::optional<BoxRule> box;
  std::optional<PlaneRule> plane;
  std::string indices;  // "1,5,9"; empty: no index rule
  std::optional<ColourRule> colour;
};

// The pinned vertices of the placed mesh, ascending. Throws sdk::Error (invalid argument)
// naming the rule and its parameter when a rule selects nothing or is malformed (an index
// list that is not whole numbers, an index past the mesh, a colour rule on a mesh without
// vertex colours).
std::vector<uint32_t> select_pins(const TriangleMesh& mesh, const PinRules& rules,
                                  const std::string& source);

}  // namespace clothlab::builtin
