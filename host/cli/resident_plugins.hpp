// Plugin libraries kept loaded across the cases one process goes through (a sweep's worker,
// the up-front check of every case): loading a library again is then a reference count, not
// a dlopen that maps and relocates it and a dlclose that unmaps it, per case. A plugin's
// static data therefore lives on from case to case, as in any program that runs several
// simulations; each case still creates its own plugin instances.
#pragma once

#include <clothlab/host/plugin_library.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <filesystem>
#include <map>

#include "run_config.hpp"
#include "simulation.hpp"

namespace clothlab::cli {

class ResidentPlugins {
 public:
  // load_plugins(config, search_path), keeping both libraries loaded from then on.
  LoadedPlugins load(const RunConfig& config, const host::PluginSearchPath& search_path);

 private:
  std::map<std::filesystem::path, host::PluginLibrary> held_;
};

}  // namespace clothlab::cli
