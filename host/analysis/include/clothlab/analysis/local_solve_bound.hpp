// The step a local (position-based) solver needs to deliver a cloth's own stiffness (issue 21).
//
// One unconverged Gauss-Seidel or Jacobi sweep per substep h moves a particle of mass m about as
// far as a spring of stiffness m / h^2 would: the inertia term of the step's local problem,
// m / h^2, outweighs any stiffer spring, and what a stiffer spring asks is left to later sweeps
// that a substep does not run. A cloth whose warp/weft springs have stiffness ks then behaves
// like a membrane of stiffness m / h^2 unless m / h^2 >~ ks, i.e. h <~ sqrt(m / ks) (the
// explicit methods' limit too, within a small factor). On a mesh, masses and ks vary spring by
// spring: the bound is the median structural spring's (its mass the mean of its two
// particles'), so neither a light corner nor one stiff edge decides it. XPBD and vertex block
// descent declare
// CLOTHLAB_TRAIT_LOCAL_SOLVES; `clothlab --choose` reports the bound beside its search.
#pragma once

#include <clothlab/core/cloth_model.hpp>
#include <cstdint>

namespace clothlab::analysis {

struct LocalSolveBound {
  double particle_mass = 0;  // kg: the median structural spring's particles' mean mass
  double stiffness = 0;      // N/m: that spring's ks
  double dt_max = 0;         // s: sqrt(particle_mass / stiffness); +inf without stiffness
  // The fewest substeps per frame at `frame_rate` (Hz) whose step is within dt_max.
  uint32_t substeps_per_frame(double frame_rate) const;
};

LocalSolveBound local_solve_bound(const ClothModel& model);

}  // namespace clothlab::analysis
