// Faulty: its integrator has no step function (a null pointer in the descriptor). The host's
// loader refuses such a descriptor at every version, so loading.abi-policy, which puts copies of
// this descriptor with other versions through that loader's gate, fails: it tests the real
// loader on the real descriptor, not the version rule alone (which this plugin keeps).
#include "symplectic_euler.hpp"

struct LacksStep : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "lacks-step";
  static constexpr const char* name = "Integrator without a step function";
  static constexpr const char* description = "faulty: step is a null pointer";
};

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  static const clothlab_integrator without_step = [] {
    clothlab_integrator integrator = *clothlab::sdk::integrators<LacksStep>::list()[0];
    integrator.step = nullptr;
    return integrator;
  }();
  static const clothlab_integrator* const integrators[] = {&without_step};
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR},
      sizeof(clothlab_plugin_descriptor),
      1,
      0,
      0,
      "faulty-lacks-step",
      "0.0.1",
      integrators,
      nullptr,
  };
  return &descriptor;
}
