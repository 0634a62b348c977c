// clothlab.Simulation: one session (host/session) stepped from Python.
#pragma once

#include <pybind11/pybind11.h>

#include <clothlab/host/plugin_search_path.hpp>
#include <string>
#include <vector>

namespace clothlab::python {

// The plugin_path argument's folders, CLOTHLAB_PLUGIN_PATH's, then the plugin folders found
// from this module's own file: inside the package (pip), the install tree's, the build tree's.
host::PluginSearchPath module_search_path(const std::vector<std::string>& plugin_path);

void bind_simulation(pybind11::module_& module);

}  // namespace clothlab::python
