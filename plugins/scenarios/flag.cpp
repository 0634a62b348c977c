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
#include <cmath>
#include <cstdio>
#include <vector>

#include "grid_cloth.hpp"

namespace clothlab::builtin {

struct FlagInWind {
  static constexpr const char* id = "flag";
  static constexpr const char* name = "Flag in wind";
  static constexpr const char* version = "1.0.0";
  static constexpr const char* description =
      "Flag with its left column pinned to a pole, gravity and wind";
  static constexpr auto params =
      concat(grid_cloth_params(),
             std::array{
                 sdk::vec3_param("wind.direction", {1.0, 0.0, 0.5}, -1e3, 1e3, "",
                                 "direction the wind blows towards (normalised; only its component "
                                 "along the cloth normal pushes)"),
                 sdk::real_param("wind.strength", 5.0, 0.0, 1e4, "N/m^2",
                                 "the seed's wind pressure along the cloth normal; 0 = none"),
                 sdk::real_param("air.density", 0.0, 0.0, 100.0, "kg/m^3",
                                 "air for the drag and lift model (1.225 at sea level); 0 = none"),
                 sdk::real_param("air.speed", 3.0, 0.0, 1e3, "m/s",
                                 "the air's speed along wind.direction (drag and lift model)"),
                 sdk::real_param("air.drag", 1.2, 0.0, 10.0, "", "drag coefficient of a triangle"),
                 sdk::real_param("air.lift", 1.0, 0.0, 10.0, "", "lift coefficient of a triangle"),
             });

  explicit FlagInWind(const sdk::Params& values)
      : cloth_(values), wind_strength_(values.real("wind.strength")) {
    air_.struct_size = sizeof air_;
    air_.density = values.real("air.density");
    air_.drag_coefficient = values.real("air.drag");
    air_.lift_coefficient = values.real("air.lift");
    const std::array<double, 3> direction = values.vec3("wind.direction");
    const double length = std::hypot(direction[0], direction[1], direction[2]);
    if ((wind_strength_ > 0.0 || air_.density > 0.0) && !(length > 0.0)) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "parameter wind.direction = (%g, %g, %g) must be non-zero when "
                    "wind.strength > 0 or air.density > 0",
                    direction[0], direction[1], direction[2]);
      throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, text);
    }
    for (int k = 0; k < 3; ++k) wind_direction_[k] = length > 0.0 ? direction[k] / length : 0.0;
    for (int k = 0; k < 3; ++k)
      air_.wind_velocity[k] = wind_direction_[k] * values.real("air.speed");
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
    if (wind_strength_ > 0.0) {
      scene.wind_strength = wind_strength_;
      for (int k = 0; k < 3; ++k) scene.wind_direction[k] = wind_direction_[k];
    }
  }

  clothlab_air air() const { return air_; }

 private:
  GridCloth cloth_;
  double wind_strength_;
  clothlab_air air_{};
  std::array<double, 3> wind_direction_{};
  std::vector<uint32_t> pinned_;
};

}  // namespace clothlab::builtin

CLOTHLAB_PLUGIN_ENTRY("clothlab-builtin-flag", "1.0.0", clothlab::sdk::integrators<>,
                      clothlab::sdk::scenarios<clothlab::builtin::FlagInWind>)
