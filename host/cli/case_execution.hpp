// One case as JSON, for single runs, sweeps and the dt search alike: the same Simulation,
// reported the same way. Meant to run inside run_isolated (isolation.hpp).
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <clothlab/host/run_summary.hpp>
#include <nlohmann/json.hpp>
#include <vector>

#include "run_config.hpp"
#include "simulation.hpp"

namespace clothlab::cli {

// One case's run as the worker child answers it: {"summary": the run JSON, "positions": final x,
// particle-major, "diagonal": the cloth's, m} (the last two when asked for).
struct CaseRun {
  host::RunSummary summary;
  std::vector<double> positions;  // empty for a run that was not stable (non-finite)
  double diagonal = 0;
};
// Reads the answer; throws InputError naming a field that is missing, unknown or mistyped.
CaseRun case_run_from_json(const nlohmann::json& answer);

// Runs the configured case and returns its answer (CaseRun), with the positions when asked.
nlohmann::json run_case(const RunConfig& config, const host::PluginSearchPath& search_path,
                        bool with_positions = false);
// The same with the plugins already loaded (load_plugins).
nlohmann::json run_case(const RunConfig& config, LoadedPlugins plugins, bool with_positions);

// The dt_max predicted for the configured integrator on the configured scene from the
// float64 linearisation at rest, with damping: {"dt_max", "omega_max", "dominant_re",
// "dominant_im", "method"}. dt_max is null when never unstable. Throws for an integrator the
// analysis does not know.
nlohmann::json predict_case(const RunConfig& config, const host::PluginSearchPath& search_path);
nlohmann::json predict_case(const RunConfig& config, LoadedPlugins plugins);

// For an integrator that declares CLOTHLAB_TRAIT_LOCAL_SOLVES, the step below which it delivers
// the scene's warp/weft stiffness (analysis/local_solve_bound.hpp): {"dt_max", "particle_mass",
// "stiffness"}, dt_max null without stiffness; null for any other integrator.
nlohmann::json local_solve_case(const RunConfig& config, LoadedPlugins plugins);

// Loads the configured plugins and applies the parameter values, in a child process: a search
// or a choice that runs many cases checks them once first, so bad input (a plugin that is not
// there, a value it refuses) is reported with where it was set instead of as failed runs.
void check_plugins(const RunConfig& config, const host::PluginSearchPath& search_path);

}  // namespace clothlab::cli
