// Where the mesh goes: p' = translation + Rz Ry Rx (scale p), the rotation in degrees about
// the fixed x, then y, then z axis through the file's origin.
#pragma once

#include <array>
#include <cmath>
#include <numbers>

#include "triangle_mesh.hpp"

namespace clothlab::builtin {

struct Placement {
  double scale;
  std::array<double, 3> rotation_degrees;
  std::array<double, 3> translation;
};

inline void place(TriangleMesh& mesh, const Placement& placement) {
  std::array<double, 3> c{}, s{};
  for (int k = 0; k < 3; ++k) {
    const double radians = placement.rotation_degrees[k] * std::numbers::pi / 180.0;
    c[k] = std::cos(radians);
    s[k] = std::sin(radians);
  }
  for (std::array<double, 3>& p : mesh.positions) {
    double x = placement.scale * p[0], y = placement.scale * p[1], z = placement.scale * p[2];
    double t = c[0] * y - s[0] * z;  // about x
    z = s[0] * y + c[0] * z;
    y = t;
    t = c[1] * x + s[1] * z;  // about y
    z = -s[1] * x + c[1] * z;
    x = t;
    t = c[2] * x - s[2] * y;  // about z
    y = s[2] * x + c[2] * y;
    x = t;
    p = {x + placement.translation[0], y + placement.translation[1], z + placement.translation[2]};
  }
}

}  // namespace clothlab::builtin
