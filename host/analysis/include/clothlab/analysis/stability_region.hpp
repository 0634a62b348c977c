// Stability on the linear test problems and the largest stable dt it predicts: of any declared
// explicit Runge-Kutta-Nystrom table (RknTable, from the amplification matrix of one step on
// the damped oscillator), and in closed form for the classic methods (Method).
//
// RK-type methods (explicit Euler, midpoint, RK4) act on y' = lambda y through their stability
// polynomial R(z), z = lambda dt; stable when |R(z)| <= 1. Real-axis intervals: Euler 2, midpoint
// 2, RK4 2.785; imaginary axis: Euler 0, midpoint 0 (|R(iy)|^2 = 1 + y^4/4), RK4 2.828.
// The symplectic Euler of the seed (v += dt a(x, v); x += dt v) and position Verlet
// (x' = x + d (x - x_prev) + dt^2 a(x), no velocity forces, retention d per step) are not RK
// maps: they are judged by the spectral radius of their 2x2 amplification matrix on the damped
// oscillator x'' + c x' + w^2 x = 0 (undamped: both need w dt < 2).
#pragma once

#include <clothlab/ext/explicit_scheme.h>

#include <array>
#include <complex>
#include <vector>

namespace clothlab::analysis {

// Closed forms of the classic methods: the oracle the declared-table analysis below is
// tested against.
enum class Method { ExplicitEuler, SymplecticEuler, Midpoint, RungeKutta4, PositionVerlet };
const char* to_string(Method method);

// One mode of the linearised cloth: x'' + damping_rate x' + omega_squared x = 0.
struct DampedMode {
  double omega_squared = 0.0;  // 1/s^2
  double damping_rate = 0.0;   // 1/s
};

// Position Verlet's own damping: the fraction of the previous displacement kept per step is
// d = 1 - per_step_fraction when per_step_fraction > 0 (the seed's 0.5 %), else exp(-rate dt).
struct VerletDamping {
  double rate_per_s = 0.0;
  double per_step_fraction = 0.0;
  double retention(double dt) const;
};

// R(z) of an RK-type method; throws std::invalid_argument for the non-RK methods.
std::complex<double> stability_polynomial(Method method, std::complex<double> z);

// Largest |eigenvalue| of one step's amplification on the mode (RK methods: both roots of the
// mode's characteristic polynomial). Verlet ignores mode.damping_rate: it sees no velocity forces.
double amplification_radius(Method method, const DampedMode& mode, double dt,
                            const VerletDamping& verlet = {});

// Largest dt such that every step in (0, dt] is stable: scans dt upward from far below the mode's
// time scale, then bisects the first loss of stability to 1e-10 relative. Returns 0 when unstable
// at any dt (e.g. explicit Euler on an undamped oscillator) and +infinity when never unstable.
double predicted_dt_max(Method method, const DampedMode& mode, const VerletDamping& verlet = {});
// The same for an RK-type method on one eigenvalue of the first-order system y' = lambda y.
double predicted_dt_max(Method method, std::complex<double> eigenvalue);

// Any explicit Runge-Kutta-Nystrom scheme an integrator declares as data
// (clothlab.explicit-scheme/1), copied out of the plugin.
struct RknTable {
  uint32_t stages = 0;
  std::vector<double> c, alpha, x_coupling, v_coupling, x_weights, v_weights;
  bool first_same_as_last = false;
  // Evaluations of a per step: stages, one fewer when the last is the next step's first.
  uint32_t evaluations_per_step() const;
};
// Throws std::invalid_argument for a malformed table (no arrays, stages outside 1 .. 8).
RknTable rkn_table(const clothlab_explicit_scheme& declared);

// One step of the table on x'' = -w^2 x - c x' (c = mode.damping_rate; 0 when the integrator
// does not pass velocities, `velocity_forces` false): (x, v) -> M (x, v), M row-major.
std::array<double, 4> amplification_matrix(const RknTable& table, const DampedMode& mode, double dt,
                                           bool velocity_forces);
double amplification_radius(const RknTable& table, const DampedMode& mode, double dt,
                            bool velocity_forces);
// Largest dt with every step in (0, dt] stable (spectral radius of M <= 1), as above.
double predicted_dt_max(const RknTable& table, const DampedMode& mode, bool velocity_forces);

}  // namespace clothlab::analysis
