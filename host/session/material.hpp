// A cloth material (per unit area, independent of the mesh) and the per-spring values it
// gives a Provot grid of a given spacing. Keys material.*; see configs/materials/README.md.
//
// The mapping, for a square grid of spacing h (structural springs along the axes, shear
// springs on the diagonals, flexion springs skipping one particle):
//   - uniform strain e along x stores 1/2 (ks_structural + ks_shear) e^2 per unit area, and a
//     shear strain g stores 1/2 ks_shear g^2: the membrane stiffnesses in N/m ARE the spring
//     constants, whatever h. So ks_shear = shear stiffness G and
//     ks_structural = stretch stiffness E - G (together they give E along each axis).
//   - bending stiffness B (N m: moment per unit width per unit curvature) has no length scale
//     of its own; a flexion spring resists a bend over a length ~h, so ks_flexion = B / h^2.
//     This is a dimensional mapping, not an equivalence (a flexion spring's resistance is of
//     higher order in the bend angle), but it keeps B's effect the same at every spacing.
//   - damping is Rayleigh stiffness-proportional, kd = damping_time * ks per family: the same
//     continuum viscosity at every spacing.
//   - total mass = areal density * width * height.
// Non-square cells use h = sqrt(h_row h_col); the membrane terms are exact only for square ones.
#pragma once

#include <clothlab/host/param_set.hpp>
#include <optional>
#include <string>

#include "settings.hpp"

namespace clothlab::cli {

struct Material {
  std::string name;              // label for reports ("cotton"); may be empty
  double areal_density = 0;      // kg/m^2
  double stretch_stiffness = 0;  // N/m, E
  double shear_stiffness = 0;    // N/m, G (per radian of shear angle)
  double bending_stiffness = 0;  // N m, B
  double damping_time = 0;       // s, kd / ks
  std::string source;            // where the first material key was set, for messages
};

struct GridSprings {
  double mass;  // kg, total
  double structural_ks, structural_kd, shear_ks, shear_kd, flexion_ks, flexion_kd;
};

GridSprings grid_springs(const Material& material, double rows, double cols, double width,
                         double height);

// Sets mass and every spring family's ks and kd on a grid scenario's parameters (rows, cols,
// width, height are read from them). Throws InputError when the scenario lacks those
// parameters or when `user_settings` (the scenario settings given) set any value the material
// decides: one or the other, never silently both.
void apply_material(const Material& material, const std::vector<Setting>& user_settings,
                    host::ParamSet& scenario_params);

}  // namespace clothlab::cli
