// Honest: one attached corner flicked once, out and back along +x within the first `flick`
// seconds (20 to 80 ms), then held: a real parameter whose effect is over long before 0.1 s,
// which scenario.params must see (and scenario.attachments must pass).
#include <array>
#include <cmath>
#include <numbers>
#include <span>

#include "../faulty/hanging_sheet.hpp"

struct FlicksACorner : clothlab::faulty::HangingSheetBase {
  static constexpr const char* id = "flicks-a-corner";
  static constexpr const char* name = "Sheet whose corner is flicked";
  static constexpr const char* description = "honest: a 5 cm flick of a corner, then at rest";
  static constexpr std::array<clothlab_param_spec, 1> params{
      clothlab::sdk::real_param("flick", 0.02, 0.02, 0.08, "s", "how long the flick takes")};

  explicit FlicksACorner(const clothlab::sdk::Params& values)
      : HangingSheetBase(8, 8), flick_(values.real("flick")) {}

  static constexpr double reach = 0.05;  // m

  std::span<const uint32_t> attached_particles() const { return {&corner_, 1}; }
  void attachment_targets(double t, std::span<double> positions,
                          std::span<double> velocities) const {
    const double phase = t < flick_ ? std::numbers::pi * t / flick_ : 0.0;
    positions[0] = -0.5 + reach * std::sin(phase) * std::sin(phase);
    positions[1] = 1.0;
    positions[2] = 0.0;
    velocities[0] = reach * std::numbers::pi / flick_ * std::sin(2.0 * phase);
    velocities[1] = 0.0;
    velocities[2] = 0.0;
  }

  double flick_;
  uint32_t corner_ = 0;
};

CLOTHLAB_PLUGIN_ENTRY("flicks-a-corner", "0.0.1", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<FlicksACorner>)
