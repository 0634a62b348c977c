// --dry-run: everything a run, sweep or --choose checks before its first step, and then no step.
// The docs' commands are tested this way where running them takes minutes or needs Slurm.
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <filesystem>
#include <string>

#include "run_config.hpp"

namespace clothlab::cli {

// Loads both plugins, applies the parameters, creates the scenario, the scene, the cloth and
// the integrator (prepared) in a child process, as a run would, and returns one line saying
// what would run. Throws what the run would throw (InputError, PluginLoadError, PluginError).
std::string check_single_run(const RunConfig& config, const host::PluginSearchPath& search_path);

// A folder the run creates (--frames, a sweep's or --choose's output folder): its nearest
// existing ancestor must be a folder the program may write into. InputError naming `source`.
void check_creatable_folder(const std::filesystem::path& folder, const std::string& source);

}  // namespace clothlab::cli
