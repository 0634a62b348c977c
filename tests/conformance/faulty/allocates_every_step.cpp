// Faulty: allocates scratch on the heap in every step instead of in prepare
// (robustness.no-alloc catches it).
#include <vector>

#include "symplectic_euler.hpp"

struct AllocatesEveryStep : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "allocates-every-step";
  static constexpr const char* name = "Integrator that allocates in step";
  static constexpr const char* description = "faulty: a std::vector per step";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    std::vector<Real> acceleration(3 * system.stride());
    system.acceleration(t, system.x(), system.v(), acceleration.data());
    system.axpy(system.v(), dt, acceleration.data());
    system.axpy(system.x(), dt, system.v());
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-allocates-every-step", "0.0.1",
                      clothlab::sdk::integrators<AllocatesEveryStep>, clothlab::sdk::scenarios<>)
