// Faulty: its collider (clothlab.colliders/2) reports itself at rest while its poses move it at
// 3 m/s (scenario.colliders catches the velocity its poses do not follow).
#include "collider_sheet.hpp"

struct MisstatesItsColliderVelocity : clothlab::faulty::ColliderSheetBase {
  using ColliderSheetBase::ColliderSheetBase;
  static constexpr const char* id = "misstates-its-collider-velocity";
  static constexpr const char* name = "Sheet whose collider misstates its velocity";
  static constexpr const char* description =
      "faulty: the sphere moves at 3 m/s along x and reports a velocity of 0";

  std::span<const clothlab_collider> colliders() const { return {&sphere_, 1}; }
  clothlab_collider_motion collider_motion(uint32_t, double t) const {
    clothlab_collider_motion motion{};
    motion.pose = {{3.0 * t, 0.0, 0.5}, {1.0, 0.0, 0.0, 0.0}};
    return motion;
  }

  clothlab_collider sphere_ = sphere(0.2);
};

CLOTHLAB_PLUGIN_ENTRY("faulty-misstates-its-collider-velocity", "0.0.1",
                      clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<MisstatesItsColliderVelocity>)
