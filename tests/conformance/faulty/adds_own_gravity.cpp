// Faulty: adds gravity itself on top of the host's forces (which already hold the scene's
// gravity), so a cloth without external forces starts to fall; numerics.rest catches it.
#include "symplectic_euler.hpp"

struct AddsOwnGravity : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "adds-own-gravity";
  static constexpr const char* name = "Symplectic Euler with built-in gravity";
  static constexpr const char* description = "faulty: adds 9.81 m/s^2 along -y itself";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    Real* a = static_cast<Real*>(acceleration_);
    system.acceleration(t, system.x(), system.v(), a);
    const uint32_t stride = system.stride();
    for (uint32_t i = 0; i < system.particle_count(); ++i)
      if (system.inverse_mass()[i] != Real(0)) a[stride + i] -= Real(9.81);
    system.axpy(system.v(), dt, a);
    system.axpy(system.x(), dt, system.v());
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-adds-own-gravity", "0.0.1",
                      clothlab::sdk::integrators<AddsOwnGravity>, clothlab::sdk::scenarios<>)
