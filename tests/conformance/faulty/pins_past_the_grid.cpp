// Faulty: also pins the bottom-right corner, but counts it from 1 (rows * cols, one past the
// last index): the scene names a particle outside the grid, which scenario.valid catches.
#include "hanging_sheet.hpp"

struct PinsPastTheGrid : clothlab::faulty::HangingSheetBase {
  explicit PinsPastTheGrid(const clothlab::sdk::Params& values)
      : HangingSheetBase(values), corners_{0, cols_ - 1, rows_ * cols_} {}
  static constexpr const char* id = "pins-past-the-grid";
  static constexpr const char* name = "Sheet pinned one past its last particle";
  static constexpr const char* description = "faulty: a pin index equals rows * cols";

  void describe(clothlab_scene& scene) const {
    HangingSheetBase::describe(scene);
    scene.pinned_count = static_cast<uint32_t>(corners_.size());
    scene.pinned = corners_.data();
  }

  std::array<uint32_t, 3> corners_;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-pins-past-the-grid", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<PinsPastTheGrid>)
