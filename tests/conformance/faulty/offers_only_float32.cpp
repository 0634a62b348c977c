// Faulty: offers float32 only (its descriptor's precision mask); the numerics are measured
// against analytic solutions in float64, so numerics.float64 fails in their place.
#include "edited_library.hpp"
#include "symplectic_euler.hpp"

struct OffersOnlyFloat32 : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "offers-only-float32";
  static constexpr const char* name = "Symplectic Euler in float32 only";
  static constexpr const char* description = "faulty: no float64";
};

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  return clothlab::faulty::edited_library<OffersOnlyFloat32>(
      "faulty-offers-only-float32",
      [](clothlab_integrator& integrator) { integrator.precisions = 1u << CLOTHLAB_FLOAT32; });
}
