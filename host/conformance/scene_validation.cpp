#include "scene_validation.hpp"

#include <cmath>
#include <string>

#include "verdict.hpp"

namespace clothlab::conformance {
namespace {

bool finite3(const double (&v)[3]) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

double norm3(const double (&v)[3]) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

void require_family(const char* name, const clothlab_spring_family& family) {
  require(std::isfinite(family.ks) && family.ks >= 0 && std::isfinite(family.kd) && family.kd >= 0,
          std::string(name) + " ks " + std::to_string(family.ks) + ", kd " +
              std::to_string(family.kd) + ": must be finite and >= 0");
}

void require_unit(const char* name, const double (&v)[3]) {
  require(
      finite3(v) && std::abs(norm3(v) - 1.0) < 1e-9,
      std::string(name) + " has length " + std::to_string(norm3(v)) + "; must be a unit vector");
}

}  // namespace

void require_valid_scene(const clothlab_scene& scene) {
  require(scene.rows >= 1 && scene.cols >= 1,
          "grid " + std::to_string(scene.rows) + "x" + std::to_string(scene.cols) + " is empty");
  const uint64_t particles = uint64_t{scene.rows} * scene.cols;
  require(scene.pinned_count == 0 || scene.pinned != nullptr, "pinned is null");
  for (uint32_t i = 0; i < scene.pinned_count; ++i)
    require(scene.pinned[i] < particles, "pin " + std::to_string(scene.pinned[i]) +
                                             " outside the " + std::to_string(particles) +
                                             "-particle grid");
  require(std::isfinite(scene.total_mass) && scene.total_mass > 0,
          "total_mass " + std::to_string(scene.total_mass) + " must be > 0");
  // Spacing, hence every rest length, is positive along each dimension with 2+ particles.
  require(scene.cols == 1 || (std::isfinite(scene.width) && scene.width > 0),
          "width " + std::to_string(scene.width) + " must be > 0 with " +
              std::to_string(scene.cols) + " columns");
  require(scene.rows == 1 || (std::isfinite(scene.height) && scene.height > 0),
          "height " + std::to_string(scene.height) + " must be > 0 with " +
              std::to_string(scene.rows) + " rows");
  require(finite3(scene.origin), "origin is not finite");
  require_unit("col_axis", scene.col_axis);
  require_unit("row_axis", scene.row_axis);
  const double dot = scene.col_axis[0] * scene.row_axis[0] + scene.col_axis[1] * scene.row_axis[1] +
                     scene.col_axis[2] * scene.row_axis[2];
  require(std::abs(std::abs(dot) - 1.0) > 1e-9, "col_axis and row_axis are parallel");
  require_family("structural", scene.structural);
  require_family("shear", scene.shear);
  require_family("flexion", scene.flexion);
  require(finite3(scene.gravity), "gravity is not finite");
  require(std::isfinite(scene.wind_strength), "wind_strength is not finite");
  if (scene.wind_strength != 0) require_unit("wind_direction", scene.wind_direction);
}

}  // namespace clothlab::conformance
