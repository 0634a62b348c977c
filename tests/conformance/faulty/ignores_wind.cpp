// Faulty: declares a wind parameter but never writes it into the scene (scenario.params
// catches it: every parameter must change the scene).
#include "hanging_sheet.hpp"

struct IgnoresWind : clothlab::faulty::HangingSheetBase {
  using HangingSheetBase::HangingSheetBase;
  static constexpr const char* id = "ignores-wind";
  static constexpr const char* name = "Sheet that ignores its wind parameter";
  static constexpr const char* description = "faulty: the wind parameter changes nothing";

  void describe(clothlab_scene& scene) const {
    HangingSheetBase::describe(scene);
    scene.wind_strength = 0.0;
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-ignores-wind", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<IgnoresWind>)
