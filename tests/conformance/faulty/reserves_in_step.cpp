// Faulty: readies the host's Jacobian on first use, in its first step, instead of in prepare.
// The plugin's own code never allocates, so counting its allocator calls passes it; but the
// host allocates the Jacobian's storage inside that step. robustness.no-alloc refuses the
// prepare-only call after prepare.
#include <clothlab/sdk.hpp>

#include "symplectic_euler.hpp"

struct ReservesInStep : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "reserves-in-step";
  static constexpr const char* name = "Integrator that reserves the Jacobian in step";
  static constexpr const char* description = "faulty: jacobian reserve on first use, in step";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    if (!reserved_) {
      system.jacobian().reserve();
      reserved_ = true;
    }
    // A Jacobian product it does not need, so that the reserve is used.
    Real* a = static_cast<Real*>(acceleration_);
    system.jacobian().apply(t, system.x(), system.v(), 0.0, 0.0, system.v(), a);
    SymplecticEulerBase::step(system, t, dt);
  }

  bool reserved_ = false;
};

CLOTHLAB_PLUGIN_ENTRY("faulty-reserves-in-step", "0.0.1",
                      clothlab::sdk::integrators<ReservesInStep>, clothlab::sdk::scenarios<>)
