// Highest frequencies of the cloth linearised about a state (normally the rest layout), and the
// largest stable dt each integrator is predicted to allow there.
#pragma once

#include <clothlab/plugin.h>

#include <complex>
#include <cstdint>
#include <vector>

#include "clothlab/analysis/stability_region.hpp"

namespace clothlab::analysis {

struct SpectralOptions {
  int max_iterations = 400;   // power iterations per operator
  double tolerance = 1e-6;    // relative change of the Rayleigh quotient that ends them
  int krylov_dimension = 30;  // Arnoldi basis for the damped first-order system
  int arnoldi_restarts = 4;
  uint64_t seed = 1;  // start vectors are pseudo-random from this seed
};

struct SpectralEstimate {
  // Power iteration on J_x = da/dx (velocity-free, the M^-1 K part): w_max = sqrt(-lambda_max).
  double omega_max = 0.0;
  DampedMode stiffest_mode;  // (w_max^2, damping rate -u.J_v u / u.u along its vector u)
  // Power iteration on J_v = da/dv: the fastest damping rate and the stiffness along its vector.
  DampedMode most_damped_mode;
  // Arnoldi on the first-order system [[0, I], [J_x, J_v]]: the converged outer eigenvalues
  // (relative residual <= 1e-3, modulus >= 0.1 of the largest), largest first, and the dominant.
  std::vector<std::complex<double>> outer_eigenvalues;
  // The oscillator (w^2, c) of each outer eigenvalue's mode, in the same order: the Rayleigh
  // quotients of -J_x and -J_v on its eigenvector's position part (negative values as 0).
  std::vector<DampedMode> outer_modes;
  std::complex<double> dominant_eigenvalue;
  bool power_iterations_converged = false;
  uint64_t acceleration_evaluations = 0;
};

// Linearises the float64 system about its current state at time t; the state is left unchanged.
// Build the system with velocity forces to see damping.
SpectralEstimate estimate_spectrum(const clothlab_system& system, double t,
                                   const SpectralOptions& options = {});

// Predicted dt_max for a method from the estimate:
//  - position Verlet: the undamped stiffest mode with Verlet's own damping (it sees no
//    velocity forces);
//  - symplectic Euler: the smaller limit of the stiffest and the most damped mode, each by its
//    2x2 amplification matrix;
//  - RK methods: the smallest limit over those two modes and the outer eigenvalues (a positive
//    real part, noise on an undamped mode, is taken as 0).
double predict_dt_max(Method method, const SpectralEstimate& estimate,
                      const VerletDamping& verlet = {});
// The same for a declared table: the smallest limit over the stiffest and the most damped
// mode and every outer mode (outer_modes: for an underdamped mode w^2 = |lambda|^2 and
// c = -2 Re lambda; an overdamped one keeps both of its real roots). Without velocity forces
// only the stiffest mode, undamped, counts: the integrator sees no damping.
double predict_dt_max(const RknTable& table, const SpectralEstimate& estimate,
                      bool velocity_forces);

}  // namespace clothlab::analysis
