// Faulty: its sphere has radius -0.2 m (scenario.colliders catches it).
#include <cmath>

#include "collider_sheet.hpp"

struct GivesANegativeRadius : clothlab::faulty::ColliderSheetBase {
  using ColliderSheetBase::ColliderSheetBase;
  static constexpr const char* id = "gives-a-negative-radius";
  static constexpr const char* name = "Sheet over a sphere of negative radius";
  static constexpr const char* description = "faulty: the sphere's radius is -0.2 m";

  std::span<const clothlab_collider> colliders() const { return {&sphere_, 1}; }
  clothlab_pose collider_pose(uint32_t, double t) const { return swinging(t); }

  clothlab_collider sphere_ = sphere(-0.2);
};

CLOTHLAB_PLUGIN_ENTRY("faulty-gives-a-negative-radius", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<GivesANegativeRadius>)
