// Ctrl-C (SIGINT) and SIGTERM as a request to stop a run cleanly: the step loop sees the
// flag, the run ends with its outputs (summary, frames and their index) written.
// A second signal terminates at once (the handler is reset after the first).
#pragma once

#include <atomic>

namespace clothlab::cli {

void install_interrupt_handler();
const std::atomic<bool>& interrupt_requested();

}  // namespace clothlab::cli
