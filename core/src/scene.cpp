// Copies a scenario's clothlab_scene into an owned Scene and rejects anything the core
// cannot simulate or the header's contract forbids, with a message naming the field, its
// value and the allowed range. The one scene validation: the conformance runner uses it too.
#include <algorithm>
#include <clothlab/core/cloth.hpp>
#include <clothlab/core/triangle_mesh.hpp>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "value_text.hpp"

namespace clothlab {
namespace {

constexpr double unit_tolerance = 1e-9;

[[noreturn]] void reject(const std::string& field, const std::string& value,
                         const std::string& allowed) {
  throw std::invalid_argument((field.starts_with("air.") ? "" : "scene.") + field + " = " + value +
                              ": allowed " + allowed);
}

std::string format(double value) { return detail::value_text(value); }

std::string format(const double (&v)[3]) {
  std::ostringstream out;
  out.precision(17);
  out << '(' << v[0] << ", " << v[1] << ", " << v[2] << ')';
  return out.str();
}

double require_positive(const char* field, double value) {
  if (!std::isfinite(value) || value <= 0.0) reject(field, format(value), "finite > 0");
  return value;
}

double require_non_negative(const char* field, double value) {
  if (!std::isfinite(value) || value < 0.0) reject(field, format(value), "finite >= 0");
  return value;
}

Vec3 require_finite(const char* field, const double (&v)[3]) {
  for (double component : v) {
    if (!std::isfinite(component)) reject(field, format(v), "finite components");
  }
  return {v[0], v[1], v[2]};
}

// The header's contract is a unit vector; rounding in the scenario's arithmetic is allowed
// (and removed: the core renormalises).
Vec3 require_unit(const char* field, const double (&v)[3]) {
  const Vec3 finite = require_finite(field, v);
  const double length =
      std::sqrt(finite[0] * finite[0] + finite[1] * finite[1] + finite[2] * finite[2]);
  if (!(std::abs(length - 1.0) <= unit_tolerance)) reject(field, format(v), "a unit vector");
  return {finite[0] / length, finite[1] / length, finite[2] / length};
}

// Spacing along a dimension with two or more particles is positive; with one it is unused.
double require_extent(const char* field, double value, uint32_t particles) {
  if (particles > 1) return require_positive(field, value);
  return require_non_negative(field, value);
}

SpringFamily require_family(const std::string& name, const clothlab_spring_family& family) {
  return {require_non_negative((name + ".ks").c_str(), family.ks),
          require_non_negative((name + ".kd").c_str(), family.kd)};
}

// Fields beyond struct_size were not written by the scenario: they read as zero.
clothlab_scene copy_of(const clothlab_scene& abi) {
  if (abi.struct_size < offsetof(clothlab_scene, total_mass)) {
    reject("struct_size", std::to_string(abi.struct_size),
           ">= " + std::to_string(offsetof(clothlab_scene, total_mass)));
  }
  clothlab_scene in;
  std::memset(&in, 0, sizeof in);
  std::memcpy(&in, &abi, std::min<std::size_t>(abi.struct_size, sizeof in));
  return in;
}

// Everything but the grid's layout: mass, springs, forces and the pins (below `particles`,
// which `limit` names).
void copy_cloth_fields(const clothlab_scene& in, uint64_t particles, const std::string& limit,
                       Scene& scene) {
  scene.total_mass = require_positive("total_mass", in.total_mass);
  scene.structural = require_family("structural", in.structural);
  scene.shear = require_family("shear", in.shear);
  scene.flexion = require_family("flexion", in.flexion);
  scene.gravity = require_finite("gravity", in.gravity);
  scene.wind_strength = require_non_negative("wind_strength", in.wind_strength);
  scene.wind_direction = {1.0, 0.0, 0.0};
  if (scene.wind_strength > 0.0) {
    scene.wind_direction = require_unit("wind_direction", in.wind_direction);
  }
  if (in.pinned_count > 0 && in.pinned == nullptr) {
    reject("pinned", "NULL with pinned_count " + std::to_string(in.pinned_count),
           "an array of pinned_count indices");
  }
  scene.pinned.assign(in.pinned, in.pinned + in.pinned_count);
  for (uint32_t index : scene.pinned) {
    if (index >= particles) {
      reject("pinned", std::to_string(index),
             "indices < " + limit + " = " + std::to_string(particles));
    }
  }
  std::sort(scene.pinned.begin(), scene.pinned.end());
  scene.pinned.erase(std::unique(scene.pinned.begin(), scene.pinned.end()), scene.pinned.end());
}

}  // namespace

Scene scene_from_abi(const clothlab_scene& abi) {
  const clothlab_scene in = copy_of(abi);
  Scene scene;
  if (in.rows < 1) reject("rows", std::to_string(in.rows), "integer >= 1");
  if (in.cols < 1) reject("cols", std::to_string(in.cols), "integer >= 1");
  scene.rows = in.rows;
  scene.cols = in.cols;
  scene.width = require_extent("width", in.width, in.cols);
  scene.height = require_extent("height", in.height, in.rows);
  scene.origin = require_finite("origin", in.origin);
  scene.col_axis = require_unit("col_axis", in.col_axis);
  scene.row_axis = require_unit("row_axis", in.row_axis);
  const double axes_dot = scene.col_axis[0] * scene.row_axis[0] +
                          scene.col_axis[1] * scene.row_axis[1] +
                          scene.col_axis[2] * scene.row_axis[2];
  if (!(std::abs(std::abs(axes_dot) - 1.0) > unit_tolerance))
    reject("row_axis", format(in.row_axis), "not parallel to col_axis " + format(in.col_axis));
  const uint64_t particles = uint64_t{in.rows} * in.cols;
  if (particles > uint64_t{UINT32_MAX} / 4) {
    reject("rows*cols", std::to_string(particles), "<= " + std::to_string(UINT32_MAX / 4));
  }
  copy_cloth_fields(in, particles, "rows*cols", scene);
  return scene;
}

Scene mesh_scene_from_abi(const clothlab_scene& abi, uint32_t vertex_count) {
  const clothlab_scene in = copy_of(abi);
  Scene scene;
  scene.rows = 0;  // not a grid: the layout fields are not read
  scene.cols = 0;
  copy_cloth_fields(in, vertex_count, "the mesh's vertex count", scene);
  return scene;
}

Air air_from_abi(const clothlab_air& abi) {
  if (abi.struct_size < sizeof(clothlab_air)) {
    reject("air.struct_size", std::to_string(abi.struct_size),
           ">= " + std::to_string(sizeof(clothlab_air)));
  }
  Air air;
  air.wind_velocity = require_finite("air.wind_velocity", abi.wind_velocity);
  air.density = require_non_negative("air.density", abi.density);
  air.drag_coefficient = require_non_negative("air.drag_coefficient", abi.drag_coefficient);
  air.lift_coefficient = require_non_negative("air.lift_coefficient", abi.lift_coefficient);
  return air;
}

}  // namespace clothlab
