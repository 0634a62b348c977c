// The one reading of a mesh value: "ROWSxCOLS", or "N" for N x N. The key table checks each
// side as a whole number; case expansion reads the sides back for its views.
#pragma once

#include <string>
#include <string_view>

namespace clothlab::config {

struct MeshSides {
  std::string rows, cols;  // as written, not yet checked
};

MeshSides mesh_sides(std::string_view text);

}  // namespace clothlab::config
