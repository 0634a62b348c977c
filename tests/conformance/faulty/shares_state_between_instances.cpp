// Faulty: velocity Verlet whose carried-over acceleration lives behind a static pointer (one
// for the whole process, as if there were one instance): each prepare points it at its own
// system's vector, so of two live instances the first steps with the second's acceleration.
// Runs one after the other are right; robustness.concurrent catches it.
#include "symplectic_euler.hpp"

struct SharesStateBetweenInstances : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "shares-state-between-instances";
  static constexpr const char* name = "Velocity Verlet with a process-wide acceleration";
  static constexpr const char* description =
      "faulty: the carried acceleration is shared by all instances";
  static constexpr uint32_t order = 2;

  static inline void* carried_acceleration = nullptr;

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    Real* a = system.alloc_vector();
    system.acceleration(0.0, system.x(), system.v(), a);
    carried_acceleration = a;
  }

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    Real* a = static_cast<Real*>(carried_acceleration);
    system.axpy(system.v(), 0.5 * dt, a);
    system.axpy(system.x(), dt, system.v());
    system.acceleration(t + dt, system.x(), system.v(), a);
    system.axpy(system.v(), 0.5 * dt, a);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-shares-state-between-instances", "0.0.1",
                      clothlab::sdk::integrators<SharesStateBetweenInstances>,
                      clothlab::sdk::scenarios<>)
