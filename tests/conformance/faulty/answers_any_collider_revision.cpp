// Faulty: answers "clothlab.colliders/N" for every N with its /1 table, so a host that asks for a
// later revision would read a /1 table as the newer one (descriptor.extensions catches it).
#include <string_view>

#include "collider_sheet.hpp"

struct AnswersAnyColliderRevision : clothlab::faulty::ColliderSheetBase {
  using ColliderSheetBase::ColliderSheetBase;
  static constexpr const char* id = "answers-any-collider-revision";
  static constexpr const char* name = "Sheet whose colliders answer any revision";
  static constexpr const char* description =
      "faulty: clothlab.colliders/0 and /3 give the /1 table";

  std::span<const clothlab_collider> colliders() const { return {&sphere_, 1}; }
  clothlab_pose collider_pose(uint32_t, double t) const { return swinging(t); }

  static const void* extension(std::string_view requested) noexcept {
    if (!requested.starts_with("clothlab.colliders/")) return nullptr;
    return clothlab::sdk::scenario_extension<AnswersAnyColliderRevision>(CLOTHLAB_EXT_COLLIDERS);
  }

  clothlab_collider sphere_ = sphere(0.2);
};

CLOTHLAB_PLUGIN_ENTRY("faulty-answers-any-collider-revision", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<AnswersAnyColliderRevision>)
