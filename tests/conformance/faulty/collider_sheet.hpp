// The hanging sheet with one collider below it (a sphere under its middle) whose shape and path
// the faulty collider scenarios each get wrong in one way.
#pragma once

#include <clothlab/ext/colliders.h>

#include <cmath>
#include <span>

#include "hanging_sheet.hpp"

namespace clothlab::faulty {

struct ColliderSheetBase : HangingSheetBase {
  using HangingSheetBase::HangingSheetBase;

  static clothlab_collider sphere(double radius) {
    clothlab_collider collider{};
    collider.struct_size = sizeof collider;
    collider.shape = CLOTHLAB_COLLIDER_SPHERE;
    collider.radius = radius;
    collider.friction = 0.5;
    collider.thickness = 0.005;
    return collider;
  }
  // Swinging slowly to and fro under the sheet: an honest, continuous path.
  static clothlab_pose swinging(double t) {
    return {{0.2 * std::sin(t), 0.0, 0.5}, {1.0, 0.0, 0.0, 0.0}};
  }
};

}  // namespace clothlab::faulty
