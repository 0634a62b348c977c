// The clothlab program's use of the one child-process runner (clothlab::process): plugin
// code runs in a child whose JSON answer comes back, so a crash, hang or runaway exception
// ends only that child.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>

namespace clothlab::cli {

// Runs work() in a child and returns its JSON. Throws std::runtime_error with a one-line
// reason when the child threw (its message), crashed (the signal or exit status) or
// outlived timeout_s. Throws InputError / PluginLoadError / PluginError as the child did,
// so exit codes do not depend on where the work ran.
nlohmann::json run_isolated(const std::function<nlohmann::json()>& work, double timeout_s);

}  // namespace clothlab::cli
