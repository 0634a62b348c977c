// Sheet on a washing line (seed §4.1): hangs in the x-y plane, rows going down (-y), the
// top-left and top-right particles pinned, gravity the only external force.
#include <array>
#include <clothlab/sdk.hpp>
#include <vector>

#include "grid_cloth.hpp"

namespace clothlab::builtin {

struct WashingLineSheet {
  static constexpr const char* id = "sheet";
  static constexpr const char* name = "Sheet on a washing line";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Hanging sheet, top-left and top-right particles pinned, gravity only";
  static constexpr auto params = grid_cloth_params();

  explicit WashingLineSheet(const sdk::Params& values) : cloth_(values) {
    if (!cloth_.anchored) return;
    pinned_.push_back(0);                                     // top-left
    if (cloth_.cols > 1) pinned_.push_back(cloth_.cols - 1);  // top-right
  }

  void describe(clothlab_scene& scene) const {
    cloth_.fill(scene);
    // The line runs along x at y = height, centred on the origin; the sheet hangs to y = 0.
    set_vec3(scene.origin, -0.5 * cloth_.width, cloth_.height, 0.0);
    set_vec3(scene.col_axis, 1.0, 0.0, 0.0);
    set_vec3(scene.row_axis, 0.0, -1.0, 0.0);
    scene.pinned_count = static_cast<uint32_t>(pinned_.size());
    scene.pinned = pinned_.data();
  }

 private:
  GridCloth cloth_;
  std::vector<uint32_t> pinned_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-sheet", "1.0.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<clothlab::builtin::WashingLineSheet>)
