#include "pin_rules.hpp"

#include <algorithm>
#include <charconv>
#include <clothlab/sdk/error.hpp>
#include <cmath>
#include <string_view>

namespace clothlab::builtin {

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, source + ": " + what);
}

template <class Inside>
std::vector<uint32_t> vertices_where(const TriangleMesh& mesh, Inside inside) {
  std::vector<uint32_t> selected;
  for (uint32_t i = 0; i < mesh.positions.size(); ++i)
    if (inside(i)) selected.push_back(i);
  return selected;
}

std::vector<uint32_t> parse_indices(const std::string& text, uint32_t count,
                                    const std::string& source) {
  std::vector<uint32_t> selected;
  std::string_view rest = text;
  // A YAML list, pin.indices: [1, 5, 9], arrives as its text "[1, 5, 9]".
  while (!rest.empty() && rest.front() == ' ') rest.remove_prefix(1);
  while (!rest.empty() && rest.back() == ' ') rest.remove_suffix(1);
  if (rest.size() >= 2 && rest.front() == '[' && rest.back() == ']')
    rest = rest.substr(1, rest.size() - 2);
  while (!rest.empty()) {
    const size_t comma = rest.find(',');
    std::string_view item = rest.substr(0, comma);
    rest = comma == rest.npos ? std::string_view() : rest.substr(comma + 1);
    while (!item.empty() && item.front() == ' ') item.remove_prefix(1);
    while (!item.empty() && item.back() == ' ') item.remove_suffix(1);
    uint64_t index = 0;
    const auto [end, error] = std::from_chars(item.data(), item.data() + item.size(), index);
    if (item.empty() || error != std::errc() || end != item.data() + item.size())
      fail(source, "scenario.pin.indices = \"" + text + "\": \"" + std::string(item) +
                       "\" is not a vertex index; allowed: whole numbers separated by commas");
    if (index >= count)
      fail(source, "scenario.pin.indices = \"" + text + "\": vertex " + std::to_string(index) +
                       " is past the mesh's " + std::to_string(count) + " vertices");
    selected.push_back(static_cast<uint32_t>(index));
  }
  return selected;
}

void require_some(const std::vector<uint32_t>& selected, const std::string& source,
                  const std::string& rule) {
  if (selected.empty()) fail(source, "pin rule " + rule + " selects no vertex");
}

}  // namespace

std::vector<uint32_t> select_pins(const TriangleMesh& mesh, const PinRules& rules,
                                  const std::string& source) {
  std::vector<uint32_t> pinned;
  const auto add = [&](const std::vector<uint32_t>& selected) {
    pinned.insert(pinned.end(), selected.begin(), selected.end());
  };
  if (rules.box) {
    const BoxRule& box = *rules.box;
    const std::vector<uint32_t> selected = vertices_where(mesh, [&](uint32_t i) {
      for (int k = 0; k < 3; ++k)
        if (mesh.positions[i][k] < box.min[k] || mesh.positions[i][k] > box.max[k]) return false;
      return true;
    });
    require_some(selected, source, "scenario.pin.by_box (inside pin.box.min .. pin.box.max)");
    add(selected);
  }
  if (rules.plane) {
    const PlaneRule& plane = *rules.plane;
    const double length = std::hypot(plane.normal[0], plane.normal[1], plane.normal[2]);
    if (!(length > 0.0)) fail(source, "scenario.pin.plane.normal is zero; allowed: a direction");
    const std::vector<uint32_t> selected = vertices_where(mesh, [&](uint32_t i) {
      double along = 0.0;
      for (int k = 0; k < 3; ++k)
        along += (mesh.positions[i][k] - plane.point[k]) * plane.normal[k] / length;
      return std::abs(along) <= plane.distance;
    });
    require_some(selected, source,
                 "scenario.pin.by_plane (within pin.plane.distance of the plane)");
    add(selected);
  }
  if (!rules.indices.empty()) {
    const std::vector<uint32_t> selected =
        parse_indices(rules.indices, static_cast<uint32_t>(mesh.positions.size()), source);
    require_some(selected, source, "scenario.pin.indices = \"" + rules.indices + "\"");
    add(selected);
  }
  if (rules.colour) {
    if (mesh.colours.empty())
      fail(source,
           "pin rule scenario.pin.by_color needs vertex colours and the file has none (glTF "
           "COLOR_0, "
           "PLY red/green/blue, OBJ v x y z r g b)");
    const ColourRule& rule = *rules.colour;
    const std::vector<uint32_t> selected = vertices_where(mesh, [&](uint32_t i) {
      for (int k = 0; k < 3; ++k)
        if (!(std::abs(mesh.colours[i][k] - rule.colour[k]) <= rule.tolerance)) return false;
      return true;
    });
    require_some(selected, source,
                 "scenario.pin.by_color (within pin.color.tolerance of pin.color.value)");
    add(selected);
  }
  std::sort(pinned.begin(), pinned.end());
  pinned.erase(std::unique(pinned.begin(), pinned.end()), pinned.end());
  return pinned;
}

}  // namespace clothlab::builtin
