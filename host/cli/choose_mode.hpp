// `clothlab --choose`: "which integrator for my game". Takes the scene of a single-run config
// (scenario, mesh, material, frame_rate) and the choose.* keys, finds each integrator's
// cheapest passing setting (clothlab::sweep::choose_integrators) with every run in a child
// process, prints the ranked table and writes it as <choose.output>-ranked.csv / .json beside
// the probes' results store <choose.output>.csv / .json. Progress on stderr.
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <ostream>
#include <vector>

#include "settings.hpp"

namespace clothlab::cli {

// Throws InputError for bad settings, no frame_rate, or an unknown integrator. With dry_run it
// checks the scene, the candidates and the output folder, and runs nothing.
void run_choose(const std::vector<Setting>& settings, const host::PluginSearchPath& search_path,
                std::ostream& out, bool dry_run = false);

}  // namespace clothlab::cli
