// Faulty: the start-up half kick of a leapfrog start is guarded by a static flag (once per
// process) instead of being reset by prepare, so only the first instance in a process takes it:
// a second run of the same problem gives other bits. lifecycle.repeat and
// numerics.deterministic catch it.
#include "symplectic_euler.hpp"

struct StartsOncePerProcess : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "starts-once-per-process";
  static constexpr const char* name = "Leapfrog with a process-wide start-up flag";
  static constexpr const char* description = "faulty: only the first instance takes the half kick";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    static bool started = false;
    if (!started) {
      Real* a = static_cast<Real*>(acceleration_);
      system.acceleration(t, system.x(), system.v(), a);
      system.axpy(system.v(), -0.5 * dt, a);
      started = true;
    }
    SymplecticEulerBase::step(system, t, dt);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-starts-once-per-process", "0.0.1",
                      clothlab::sdk::integrators<StartsOncePerProcess>, clothlab::sdk::scenarios<>)
