// The parameters every built-in grid scenario shares, and how they fill a clothlab_scene.
//
// Defaults: a 1 m x 1 m, 0.3 kg cloth (heavy cotton, 0.3 kg/m^2) on a 50 x 50 grid,
// chosen to be STABLE for euler, midpoint, rk4 and verlet at dt = 1 ms in float32.
// On a square spring grid the in-plane stiffness (N/m) is ks and does not depend on the
// resolution, but the particle mass m = M / (rows cols) does: at 50 x 50, m = 1.2e-4 kg.
// The stiffest in-plane mode (neighbours moving against each other) has
//   w_max^2 ~ 4 (ks_structural + ks_shear) / m = 4 (20 + 10) / 1.2e-4 = 1.0e6,
// so w_max dt ~ 1.0, inside the limits of Verlet / symplectic Euler (2) and RK4 (2.8); a
// Gershgorin bound over all 12 springs of a particle, 8 sum(ks) / m, gives 1.44.
// Explicit midpoint amplifies every undamped oscillation (|R| ~ 1 + (w dt)^4 / 8 per
// step), so the high modes need damping: kd proportional to ks gives a mode the damping
// ratio zeta = (kd / ks) w / 2; kd / ks = 7e-4 puts zeta ~ 0.35 at w_max, while the fast
// real eigenvalue it adds, -(kd / ks) w^2 dt ~ -0.7, costs symplectic Euler margin (its
// limit is (w dt)^2 + 2 (kd / ks) w^2 dt < 4). More damping helps midpoint and hurts
// Euler; 7e-4 balances them. Slow swinging modes (w ~ 3 rad/s) stay practically undamped.
// Measured (2 s, float32, this core): all four stay finite up to dt = 1.4 ms in both
// scenarios (Verlet to 1.8 ms, RK4 beyond 2.5 ms). The cloth is soft: ks_structural + ks_shear =
// 30 N/m stretches ~5 % on average under its own weight, more at pinned corners; stiffer springs
// would need a smaller dt. Finer grids lighten the particles (w_max ~ 1 / spacing, the
// damping eigenvalue ~ 1 / spacing^2): scale dt down, or ks and kd, to stay stable there.
#pragma once

#include <array>
#include <clothlab/sdk.hpp>
#include <cstddef>

namespace clothlab::builtin {

inline constexpr std::size_t grid_param_count = 13;
inline constexpr double max_grid_size = 4096;

constexpr std::array<clothlab_param_spec, grid_param_count> grid_cloth_params() {
  using sdk::bool_param;
  using sdk::int_param;
  using sdk::real_param;
  using sdk::vec3_param;
  return {
      int_param("rows", 50, 1, max_grid_size, "particles along the cloth's height"),
      int_param("cols", 50, 1, max_grid_size, "particles along the cloth's width"),
      real_param("width", 1.0, 1e-3, 1e3, "m", "cloth width (along a row)"),
      real_param("height", 1.0, 1e-3, 1e3, "m", "cloth height (along a column)"),
      real_param("mass", 0.3, 1e-6, 1e6, "kg", "total mass, spread evenly over the particles"),
      real_param("structural.ks", 20.0, 0.0, 1e9, "N/m", "stiffness of structural springs"),
      real_param("structural.kd", 0.014, 0.0, 1e6, "N s/m", "damping of structural springs"),
      real_param("shear.ks", 10.0, 0.0, 1e9, "N/m", "stiffness of shear springs"),
      real_param("shear.kd", 0.007, 0.0, 1e6, "N s/m", "damping of shear springs"),
      real_param("flexion.ks", 1.0, 0.0, 1e9, "N/m", "stiffness of flexion (bend) springs"),
      real_param("flexion.kd", 0.0007, 0.0, 1e6, "N s/m", "damping of flexion springs"),
      vec3_param("gravity", {0.0, -9.81, 0.0}, -1e3, 1e3, "m/s^2", "gravitational acceleration"),
      bool_param("anchored", true,
                 "pin the scenario's anchor particles; 0 lets the whole cloth fall freely"),
  };
}

template <std::size_t N, std::size_t M>
constexpr std::array<clothlab_param_spec, N + M> concat(
    const std::array<clothlab_param_spec, N>& first,
    const std::array<clothlab_param_spec, M>& second) {
  std::array<clothlab_param_spec, N + M> all{};
  for (std::size_t i = 0; i < N; ++i) all[i] = first[i];
  for (std::size_t i = 0; i < M; ++i) all[N + i] = second[i];
  return all;
}

// The shared values, read once from validated parameters.
struct GridCloth {
  explicit GridCloth(const sdk::Params& values)
      : rows(static_cast<uint32_t>(values.integer("rows"))),
        cols(static_cast<uint32_t>(values.integer("cols"))),
        width(values.real("width")),
        height(values.real("height")),
        mass(values.real("mass")),
        structural{values.real("structural.ks"), values.real("structural.kd")},
        shear{values.real("shear.ks"), values.real("shear.kd")},
        flexion{values.real("flexion.ks"), values.real("flexion.kd")},
        gravity(values.vec3("gravity")),
        anchored(values.flag("anchored")) {}

  // Fills everything but the layout, the pins and the wind.
  void fill(clothlab_scene& scene) const {
    scene.rows = rows;
    scene.cols = cols;
    scene.width = width;
    scene.height = height;
    scene.total_mass = mass;
    scene.structural = structural;
    scene.shear = shear;
    scene.flexion = flexion;
    for (int k = 0; k < 3; ++k) scene.gravity[k] = gravity[k];
    scene.wind_strength = 0.0;
    for (double& component : scene.wind_direction) component = 0.0;
  }

  uint32_t rows, cols;
  double width, height, mass;
  clothlab_spring_family structural, shear, flexion;
  std::array<double, 3> gravity;
  bool anchored;
};

inline void set_vec3(double (&out)[3], double x, double y, double z) {
  out[0] = x;
  out[1] = y;
  out[2] = z;
}

}  // namespace clothlab::builtin
