// Jacobian-vector products of a cloth's acceleration a(t, x, v) about a fixed state, by central
// finite differences through the system's own eval_acceleration (float64 systems only).
#pragma once

#include <clothlab/plugin.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

namespace clothlab::analysis {

// Vectors have the system's layout: 3 * stride doubles, x block then y then z. Only the entries
// of active (unpinned) particles carry meaning; the others are kept at 0.
class LinearisedSystem {
 public:
  // Linearises about the system's current x and v (copied now) at time t. The system must be
  // float64 and stay alive; throws std::invalid_argument otherwise.
  LinearisedSystem(const clothlab_system& system, double t);
  ~LinearisedSystem();
  LinearisedSystem(const LinearisedSystem&) = delete;
  LinearisedSystem& operator=(const LinearisedSystem&) = delete;

  std::size_t vector_size() const;  // 3 * stride
  std::size_t active_dof() const;   // 3 * active particles

  // out = (da/dx) u: the stiffness part, M^-1 K with its sign (velocities held at the base state).
  void position_jacobian(std::span<const double> u, std::span<double> out);
  // out = (da/dv) w: the damping part (zero when the system was built without velocity forces).
  void velocity_jacobian(std::span<const double> w, std::span<double> out);

  // Over active entries only.
  double dot(std::span<const double> a, std::span<const double> b) const;
  // Zeroes every entry that does not belong to an active particle.
  void keep_active(std::span<double> u) const;

  uint64_t acceleration_evaluations() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clothlab::analysis
