// clothlab.Simulation: one session (host/session) stepped from Python.
#pragma once

#include <pybind11/pybind11.h>

#include <clothlab/config/setting.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <filesystem>
#include <string>
#include <vector>

namespace clothlab::python {

// The settings of a config given as a dict (nested or dotted keys, as a config file's) or as a
// YAML file's path, then the overrides (later wins, as --set after --config). Refuses a sweep.
std::vector<config::Setting> settings_of(const pybind11::object& config,
                                         const pybind11::dict& overrides);
// The overrides alone, as settings from "overrides" (dotted keys of --set).
std::vector<config::Setting> override_settings(const pybind11::dict& overrides);
// The folder of this module's own file (the package folder).
std::filesystem::path module_folder();

// The plugin_path argument's folders, CLOTHLAB_PLUGIN_PATH's, then the plugin folders found
// from this module's own file: inside the package (pip), the install tree's, the build tree's.
host::PluginSearchPath module_search_path(const std::vector<std::string>& plugin_path);

void bind_simulation(pybind11::module_& module);

}  // namespace clothlab::python
