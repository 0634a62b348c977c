// Runs a check body in a child process (clothlab::process), so a crash or hang in a plugin
// becomes a failed check instead of taking the runner down.
#pragma once

#include <functional>

#include "verdict.hpp"

namespace clothlab::conformance {

// Runs `body` and converts any escaping exception into a failed Verdict.
Verdict run_guarded(const std::function<Verdict()>& body);

// Runs `body` (guarded) in a child process; a child that dies by a signal, exits without
// a verdict or outlives `timeout_s` yields a failed Verdict saying so (with a sanitizer's
// summary line when one was printed).
Verdict run_isolated(const std::function<Verdict()>& body, double timeout_s);

}  // namespace clothlab::conformance
