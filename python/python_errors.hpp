// The module's exceptions: each carries the one-line message the clothlab CLI prints after
// "clothlab: error: ".
#pragma once

#include <pybind11/pybind11.h>

#include <cstdint>
#include <string>

namespace clothlab::python {

// Registers InputError (a ValueError), PluginLoadError and PluginError (RuntimeErrors),
// DivergedError (a RuntimeError with .step and .check) and the translation of the host's
// exceptions into them.
void register_errors(pybind11::module_& module);

// Raises DivergedError with the message, the failed step and the failed check.
[[noreturn]] void raise_diverged(const std::string& message, uint64_t step,
                                 const std::string& check);

}  // namespace clothlab::python
