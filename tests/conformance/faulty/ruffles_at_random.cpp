// Faulty: ruffles the sheet out of plane by a random offset drawn in describe from a generator
// that lives in the instance and advances on every call, so no two describes agree
// (scenario.deterministic catches it; a scene must follow from the parameters alone).
#include <random>

#include "hanging_sheet.hpp"

struct RufflesAtRandom : clothlab::faulty::HangingSheetBase {
  using HangingSheetBase::HangingSheetBase;
  static constexpr const char* id = "ruffles-at-random";
  static constexpr const char* name = "Sheet with a random ruffle";
  static constexpr const char* description = "faulty: describe draws a new random offset";

  void describe(clothlab_scene& scene) const {
    HangingSheetBase::describe(scene);
    scene.origin[2] = std::uniform_real_distribution<double>(-0.01, 0.01)(random_);
  }

  mutable std::minstd_rand random_{std::random_device{}()};
};

CLOTHLAB_PLUGIN_ENTRY("faulty-ruffles-at-random", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<RufflesAtRandom>)
