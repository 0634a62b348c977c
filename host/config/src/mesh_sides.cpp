#include "clothlab/config/mesh_sides.hpp"

namespace clothlab::config {

MeshSides mesh_sides(std::string_view text) {
  const size_t cross = text.find('x');
  if (cross == std::string_view::npos) return {std::string(text), std::string(text)};
  return {std::string(text.substr(0, cross)), std::string(text.substr(cross + 1))};
}

}  // namespace clothlab::config
