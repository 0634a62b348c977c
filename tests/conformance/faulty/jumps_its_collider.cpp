// Faulty: its collider teleports 2 m to the side at t = 1 s (scenario.colliders catches the jump).
#include <cmath>

#include "collider_sheet.hpp"

struct JumpsItsCollider : clothlab::faulty::ColliderSheetBase {
  using ColliderSheetBase::ColliderSheetBase;
  static constexpr const char* id = "jumps-its-collider";
  static constexpr const char* name = "Sheet whose collider jumps";
  static constexpr const char* description = "faulty: the sphere teleports 2 m at t = 1 s";

  std::span<const clothlab_collider> colliders() const { return {&sphere_, 1}; }
  clothlab_pose collider_pose(uint32_t, double t) const {
    clothlab_pose pose = swinging(t);
    if (t >= 1.0) pose.position[0] += 2.0;
    return pose;
  }

  clothlab_collider sphere_ = sphere(0.2);
};

CLOTHLAB_PLUGIN_ENTRY("faulty-jumps-its-collider", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<JumpsItsCollider>)
