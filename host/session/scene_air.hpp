// The air a scenario offers (clothlab.air/1), read and checked before the run.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/host/components.hpp>

namespace clothlab::cli {

// The scenario's air, or none (density 0) for a scenario without the extension. A malformed
// field is an InputError naming the scenario, the field, its value and what is allowed; a failing
// call is the plugin's PluginError.
Air scene_air(const host::ScenarioPlugin& scenario, const host::ScenarioInstance& instance);

}  // namespace clothlab::cli
