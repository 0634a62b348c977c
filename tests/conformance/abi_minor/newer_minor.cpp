// Sound, but built for ABI 1.(host minor + 1): a newer minor only appends fields, so the
// host must accept it (loading.abi-version and loading.host-loader pass).
#include "../faulty/symplectic_euler.hpp"

struct NewerMinor : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "newer-minor";
  static constexpr const char* name = "Symplectic Euler from a newer minor ABI";
  static constexpr const char* description = "descriptor says ABI 1.(minor + 1)";
};

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  static const clothlab_plugin_descriptor descriptor = {
      {CLOTHLAB_ABI_VERSION_MAJOR, CLOTHLAB_ABI_VERSION_MINOR + 1},
      sizeof(clothlab_plugin_descriptor),
      1,
      0,
      0,
      "abi-newer-minor",
      "0.0.1",
      clothlab::sdk::integrators<NewerMinor>::list(),
      nullptr,
  };
  return &descriptor;
}
