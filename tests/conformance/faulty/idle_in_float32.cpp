// Faulty: steps correctly in float64 and does nothing (returning OK) in float32; every check
// that runs one precision alone passes, numerics.precisions-agree catches it.
#include <type_traits>

#include "symplectic_euler.hpp"

struct IdleInFloat32 : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "idle-in-float32";
  static constexpr const char* name = "Symplectic Euler that idles in float32";
  static constexpr const char* description = "faulty: float32 steps leave the state unchanged";

  template <class Real>
  void step(clothlab::sdk::System<Real>& system, double t, double dt) {
    if constexpr (std::is_same_v<Real, double>) SymplecticEulerBase::step(system, t, dt);
  }
};

CLOTHLAB_PLUGIN_ENTRY("faulty-idle-in-float32", "0.0.1", clothlab::sdk::integrators<IdleInFloat32>,
                      clothlab::sdk::scenarios<>)
