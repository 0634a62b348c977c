// Faulty: its attachment's path is keyframed at 1 kHz and held between keys, a staircase whose
// velocity says 5 m/s: continuous at every 1 ms step start, but a 5 mm jump at each key, which a
// substep inside the step meets (scenario.attachments catches it).
#include <cmath>
#include <span>

#include "hanging_sheet.hpp"

struct HoldsItsTargetBetweenKeys : clothlab::faulty::HangingSheetBase {
  using HangingSheetBase::HangingSheetBase;
  static constexpr const char* id = "holds-its-target-between-keys";
  static constexpr const char* name = "Sheet whose attached corner moves in 1 ms stairs";
  static constexpr const char* description =
      "faulty: the corner's target is held between 1 kHz keys of a 5 m/s path";

  static constexpr double speed = 5.0;        // m/s along +x
  static constexpr double key_rate = 1000.0;  // keys per second

  std::span<const uint32_t> attached_particles() const { return {&corner_, 1}; }
  void attachment_targets(double t, std::span<double> positions,
                          std::span<double> velocities) const {
    const double key_time = std::floor(t * key_rate + 1e-6) / key_rate;
    positions[0] = -0.5 + speed * key_time;
    positions[1] = 1.0;
    positions[2] = 0.0;
    velocities[0] = speed;
    velocities[1] = 0.0;
    velocities[2] = 0.0;
  }

  uint32_t corner_ = 0;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-holds-its-target-between-keys", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<HoldsItsTargetBetweenKeys>)
