// Faulty: guards against double initialisation with a process-wide marker (an environment
// variable) that unloading does not clear, so once unloaded it cannot be loaded again in the
// same process: a host that reloads plugins gets NULL from the entry. loading.reload catches it.
#include <cstdlib>

#include "symplectic_euler.hpp"

struct RefusesSecondLoad : clothlab::faulty::SymplecticEulerBase {
  using SymplecticEulerBase::SymplecticEulerBase;
  static constexpr const char* id = "refuses-second-load";
  static constexpr const char* name = "Symplectic Euler loadable once per process";
  static constexpr const char* description = "faulty: a second load's entry returns NULL";
};

namespace {
constexpr const char* loaded_marker = "CLOTHLAB_FAULTY_REFUSES_SECOND_LOAD";
// Decided once per load, when the library's initialisers run.
const bool loaded_before = [] {
  const bool before = std::getenv(loaded_marker) != nullptr;
  setenv(loaded_marker, "1", 1);
  return before;
}();
}  // namespace

extern "C" CLOTHLAB_EXPORT const clothlab_plugin_descriptor* clothlab_plugin_entry(void) {
  if (loaded_before) return nullptr;
  return clothlab::sdk::plugin_descriptor<clothlab::sdk::integrators<RefusesSecondLoad>,
                                          clothlab::sdk::scenarios<>>("faulty-refuses-second-load",
                                                                      "0.0.1");
}
