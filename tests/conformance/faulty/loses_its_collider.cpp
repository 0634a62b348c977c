// Faulty: its collider's position turns NaN at t = 0.5 s (scenario.colliders catches it).
#include <cmath>

#include "collider_sheet.hpp"

struct LosesItsCollider : clothlab::faulty::ColliderSheetBase {
  using ColliderSheetBase::ColliderSheetBase;
  static constexpr const char* id = "loses-its-collider";
  static constexpr const char* name = "Sheet whose collider's path turns NaN";
  static constexpr const char* description = "faulty: the sphere's position is NaN from 0.5 s";

  std::span<const clothlab_collider> colliders() const { return {&sphere_, 1}; }
  clothlab_pose collider_pose(uint32_t, double t) const {
    clothlab_pose pose = swinging(t);
    if (t >= 0.5) pose.position[1] = NAN;
    return pose;
  }

  clothlab_collider sphere_ = sphere(0.2);
};

CLOTHLAB_PLUGIN_ENTRY("faulty-loses-its-collider", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<LosesItsCollider>)
