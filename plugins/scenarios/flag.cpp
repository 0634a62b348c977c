// Flag on a pole (seed §4.1): the left column is pinned along the pole (the y axis), the
// cloth starts flat in the x-y plane, and gravity plus wind act on it.
//
// The wind model pushes each triangle along its normal by (n . wind_direction) only, so a
// wind lying in the cloth's plane would never move a flat flag. The default direction,
// (1, 0, 0.5) normalised, blows mostly along the flag but has a component along its
// normal (+z); 5 N/m^2 is the dynamic pressure of a ~3 m/s breeze (rho v^2 / 2).
//
// The air (clothlab.air/1, drag and lift from the air's velocity relative to each triangle) is
// off by default (air.density 0), so the default flag is the seed's; `air.density = 1.225` with
// `wind.strength = 0` replaces the pressure by it, the wind blowing along wind.direction at
// air.speed. Its coefficients are round illustrative values (a flat plate broadside to a stream
// has a drag coefficient of about 1.2), not fitted to a fabric.
#include <clothlab/ext/air.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <vector>

#include "grid_cloth.hpp"
#include "wind_and_air.hpp"

namespace clothlab::builtin {

struct FlagInWind {
  static constexpr const char* id = "flag";
  static constexpr const char* name = "Flag in wind";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Flag with its left column pinned to a pole, gravity and wind";
  static constexpr auto params = concat(grid_cloth_params(), wind_and_air_params(5.0));

  explicit FlagInWind(const sdk::Params& values) : cloth_(values), wind_(values) {
    if (cloth_.anchored)
      for (uint32_t row = 0; row < cloth_.rows; ++row) pinned_.push_back(row * cloth_.cols);
  }

  void describe(clothlab_scene& scene) const {
    cloth_.fill(scene);
    // The pole runs along y at x = 0 from y = height down to 0; the flag extends to +x.
    set_vec3(scene.origin, 0.0, cloth_.height, 0.0);
    set_vec3(scene.col_axis, 1.0, 0.0, 0.0);
    set_vec3(scene.row_axis, 0.0, -1.0, 0.0);
    scene.pinned_count = static_cast<uint32_t>(pinned_.size());
    scene.pinned = pinned_.data();
    if (wind_.strength > 0.0) {
      scene.wind_strength = wind_.strength;
      for (int k = 0; k < 3; ++k) scene.wind_direction[k] = wind_.direction[k];
    }
  }

  clothlab_air air() const { return wind_.air; }

 private:
  GridCloth cloth_;
  WindAndAir wind_;
  std::vector<uint32_t> pinned_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-flag", "1.0.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<clothlab::builtin::FlagInWind>)
