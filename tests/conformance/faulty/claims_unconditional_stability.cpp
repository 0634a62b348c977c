// Faulty: symplectic Euler declaring CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE; at dt = 50 ms
// its explicit step blows up on the default sheet (stability.unconditional-sheet catches it).
#include "symplectic_euler.hpp"

struct ClaimsUnconditionalStability : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "claims-unconditional-stability";
  static constexpr const char* name = "Symplectic Euler claiming unconditional stability";
  static constexpr const char* description =
      "faulty: explicit, stable only below ~1.4 ms on the default sheet, declares any dt";
  static constexpr clothlab_integrator_traits traits{
      sizeof(clothlab_integrator_traits), CLOTHLAB_TRAIT_UNCONDITIONALLY_STABLE, nullptr, nullptr};
};

CLOTHLAB_PLUGIN_ENTRY("faulty-claims-unconditional-stability", "0.0.1",
                      clothlab::sdk::integrators<ClaimsUnconditionalStability>,
                      clothlab::sdk::scenarios<>)
