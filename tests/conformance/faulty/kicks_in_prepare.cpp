// Faulty: leapfrog's start-up half kick (v -= h/2 a at a nominal h = 1 ms) is taken in prepare,
// so binding an instance to a cloth moves it before any step; lifecycle.zero-steps catches it.
#include "symplectic_euler.hpp"

struct KicksInPrepare : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "kicks-in-prepare";
  static constexpr const char* name = "Leapfrog that staggers velocities in prepare";
  static constexpr const char* description = "faulty: prepare changes the velocities";

  template <class Real>
  void prepare(clothlab::sdk::System<Real>& system) {
    SymplecticEulerBase::prepare(system);
    Real* a = static_cast<Real*>(acceleration_);
    system.acceleration(0.0, system.x(), system.v(), a);
    system.axpy(system.v(), -0.5e-3, a);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-kicks-in-prepare", "0.0.1",
                      clothlab::sdk::integrators<KicksInPrepare>, clothlab::sdk::scenarios<>)
