// Runs work in a forked child so that a crash (signal, abort), a hang or a runaway exception
// in plugin code ends only that child: the caller gets an outcome it can report and goes on.
#pragma once

#include <sys/types.h>

#include <functional>
#include <string>

namespace clothlab::process {

struct IsolationOptions {
  double timeout_s = 600.0;     // the child (and its process group) is killed after this
  bool capture_stderr = false;  // keep the child's stderr (e.g. a sanitizer report) for problem
  // Called in the parent with the child's pid once it runs, and with 0 once it has ended
  // (e.g. to forward Ctrl-C to the child, which has a process group of its own).
  std::function<void(pid_t)> on_child = nullptr;
};

struct ChildOutcome {
  enum class End {
    Answered,  // work() returned; answer holds its bytes
    Threw,     // work() threw; problem holds what()
    Crashed,   // killed by a signal or exited without answering; problem says how
    TimedOut,  // outlived the deadline and was killed
  };
  End end = End::Crashed;
  std::string answer;
  // One line: "crashed: signal 11 (SIGSEGV)", "timed out after 5 s", the exception's text.
  // With capture_stderr, a crashed child's sanitizer report (its first line and its summary
  // line) is appended.
  std::string problem;
  std::string child_stderr;  // with capture_stderr: the last 64 KiB the child wrote there
  bool answered() const { return end == End::Answered; }
};

// Forks; the child resets the fault signals to their default action (so a crash is a signal
// the parent sees), asks for SIGKILL when the parent dies, runs work() and sends its bytes
// back through an O_CLOEXEC pipe, then _exits: nothing of the child, not even an exception
// thrown while answering, returns into the caller. The parent waits for the child's exit, not
// for the pipe's end, so a grandchild holding the pipe cannot stall it; the child's process
// group is killed when it ends. The parent must not have started OpenMP threads (a forked
// child of a process with a live OpenMP pool can hang).
ChildOutcome run_isolated(const std::function<std::string()>& work,
                          const IsolationOptions& options);

// "5 s", "0.2 s": a duration as the messages above write it.
std::string format_seconds(double seconds);

}  // namespace clothlab::process
