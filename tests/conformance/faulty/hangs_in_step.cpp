// Faulty: never returns from step (the runner reports "timed out after N s").
#include <chrono>
#include <thread>

#include "symplectic_euler.hpp"

struct HangsInStep : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "hangs-in-step";
  static constexpr const char* name = "Integrator that hangs";
  static constexpr const char* description = "faulty: sleeps forever in step";

  template <class Real>
  void step(clothlab::sdk::System<Real>&, double, double) {
    for (;;) std::this_thread::sleep_for(std::chrono::seconds(1));
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-hangs-in-step", "0.0.1", clothlab::sdk::integrators<HangsInStep>,
                      clothlab::sdk::scenarios<>)
