// Runs work in a forked child so that a plugin crash (signal, abort, runaway exception)
// ends only that child: a sweep records it as a failed case and goes on.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>

namespace clothlab::cli {

// Forks; the child calls work() and sends its JSON back through a pipe. Returns that JSON.
// Rethrows in the parent, as std::runtime_error with the message, an exception the child
// threw, and throws std::runtime_error naming the signal or exit status when the child died
// without answering. The parent must not have started OpenMP threads (a forked child of a
// process with a live OpenMP pool can hang): run every simulation through this function.
nlohmann::json run_isolated(const std::function<nlohmann::json()>& work);

}  // namespace clothlab::cli
