// The wind and air of the built-in scenarios that have them (flag, mesh), read from the same
// parameters: the seed's pressure wind along each triangle's normal (clothlab_scene's
// wind_direction and wind_strength) and the drag and lift model of clothlab.air/1, blowing along
// the same direction at air.speed.
#pragma once

#include <clothlab/ext/air.h>

#include <array>
#include <clothlab/sdk.hpp>
#include <cmath>
#include <cstdio>

namespace clothlab::builtin {

// The parameters; `pressure` is wind.strength's default (the flag blows by default, a mesh not).
constexpr std::array<clothlab_param_spec, 6> wind_and_air_params(double pressure) {
  return {
      sdk::vec3_param("wind.direction", {1.0, 0.0, 0.5}, -1e3, 1e3, "",
                      "direction the wind blows towards (normalised; only its component along a "
                      "triangle's normal pushes)"),
      sdk::real_param("wind.strength", pressure, 0.0, 1e4, "N/m^2",
                      "wind pressure along each triangle's normal; 0 = none"),
      sdk::real_param("air.density", 0.0, 0.0, 100.0, "kg/m^3",
                      "air for the drag and lift model (1.225 at sea level); 0 = none"),
      sdk::real_param("air.speed", 3.0, 0.0, 1e3, "m/s",
                      "the air's speed along wind.direction (drag and lift model)"),
      sdk::real_param("air.drag", 1.2, 0.0, 10.0, "", "drag coefficient of a triangle"),
      sdk::real_param("air.lift", 1.0, 0.0, 10.0, "", "lift coefficient of a triangle"),
  };
}

// The values, read once from validated parameters. A direction of length 0 is refused only
// where something blows along it.
struct WindAndAir {
  explicit WindAndAir(const sdk::Params& values) : strength(values.real("wind.strength")) {
    air.struct_size = sizeof air;
    air.density = values.real("air.density");
    air.drag_coefficient = values.real("air.drag");
    air.lift_coefficient = values.real("air.lift");
    const std::array<double, 3> given = values.vec3("wind.direction");
    const double length = std::hypot(given[0], given[1], given[2]);
    if ((strength > 0.0 || air.density > 0.0) && !(length > 0.0)) {
      char text[200];
      std::snprintf(text, sizeof text,
                    "parameter wind.direction = (%g, %g, %g) must be non-zero when "
                    "wind.strength > 0 or air.density > 0",
                    given[0], given[1], given[2]);
      throw sdk::Error(CLOTHLAB_ERROR_INVALID_ARGUMENT, text);
    }
    for (int k = 0; k < 3; ++k) direction[k] = length > 0.0 ? given[k] / length : 0.0;
    for (int k = 0; k < 3; ++k) air.wind_velocity[k] = direction[k] * values.real("air.speed");
  }

  double strength;                    // N/m^2, the pressure wind; 0 = none
  std::array<double, 3> direction{};  // unit where anything blows
  clothlab_air air{};
};

}  // namespace clothlab::builtin
