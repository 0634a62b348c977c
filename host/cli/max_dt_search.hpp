// --find-max-dt: the largest stable dt of one integrator on one scene, measured by bracketing
// and bisecting real runs of the configured duration, printed beside the predicted dt_max.
#pragma once

#include <clothlab/host/plugin_search_path.hpp>
#include <nlohmann/json.hpp>

#include "run_config.hpp"

namespace clothlab::cli {

// Every probe runs in its own child process with the objective stability verdict; a probe
// that crashes or throws counts as unstable. The prediction failing is noted, not fatal.
// Returns {integrator, scenario, rows, cols, precision, duration, tolerance, dt_max,
// dt_unstable, outcome, evaluations, predicted_dt_max, measured_over_predicted, ..., probes}.
// With `show_progress` (stderr is a terminal) each probe updates the sweeps' progress line,
// counted against find_max_dt.max_evaluations (the search usually ends sooner).
nlohmann::json find_max_dt(const Configuration& whole, const host::PluginSearchPath& search_path,
                           bool show_progress);

std::string max_dt_summary(const nlohmann::json& result);

}  // namespace clothlab::cli
