#include "resident_plugins.hpp"

namespace clothlab::cli {

LoadedPlugins ResidentPlugins::load(const RunConfig& config,
                                    const host::PluginSearchPath& search_path) {
  LoadedPlugins plugins = load_plugins(config, search_path);
  for (const host::PluginLibrary* library :
       {&plugins.integrator_library, &plugins.scenario_library})
    held_.try_emplace(library->path(), *library);
  return plugins;
}

}  // namespace clothlab::cli
