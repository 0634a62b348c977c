// The clothlab program's use of the one child-process runner (clothlab::process): plugin
// code runs in a child whose JSON answer comes back, so a crash, hang or runaway exception
// ends only that child, and is reported with the plugin call it happened in.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>

namespace clothlab::cli {

// Runs work() in a child and returns its JSON. Throws std::runtime_error with a one-line
// reason when the child threw (its message), crashed (the signal or exit status) or
// outlived timeout_s; a crash or timeout inside a plugin call names it (plugin_call_marker.hpp):
// "crashed: signal 11 (SIGSEGV) in ID.PHASE (LIBRARY) at step N". Throws InputError /
// PluginLoadError / PluginError as the child did, so exit codes do not depend on where the work
// ran. With forward_interrupt, a SIGINT or SIGTERM the program gets (interrupt.hpp) is passed on to
// the child.
nlohmann::json run_isolated(const std::function<nlohmann::json()>& work, double timeout_s,
                            bool forward_interrupt = false);

}  // namespace clothlab::cli
