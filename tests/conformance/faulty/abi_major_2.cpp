// Faulty: claims to be built for ABI 2.0 (loading.abi-version refuses it; nothing else of
// it is read).
#include "symplectic_euler.hpp"

struct AbiMajorTwo : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "abi-major-2";
  static constexpr const char* name = "Integrator built for ABI 2";
  static constexpr const char* description = "faulty: descriptor says ABI 2.0";
};

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR + 1, 0},
      sizeof(clothlab_plugin_descriptor),
      1,
      0,
      0,
      "faulty-abi-major-2",
      "0.0.1",
      clothlab::sdk::integrators<AbiMajorTwo>::list(),
      nullptr,
  };
  return &descriptor;
}
