// Ctrl-C (SIGINT) and SIGTERM as a request to stop a run cleanly: the step loop sees the
// flag, the run ends with its outputs (summary, frames and their index) written.
// A second signal terminates at once (the handler is reset after the first). The run steps in
// a child process with a process group of its own, which the terminal's Ctrl-C does not
// reach: the parent passes the signal on.
#pragma once

#include <sys/types.h>

#include <atomic>

namespace clothlab::cli {

void install_interrupt_handler();
const std::atomic<bool>& interrupt_requested();
// The process that gets the signals from now on (0: none). Safe to call at any time.
void forward_interrupts_to(pid_t child);

}  // namespace clothlab::cli
