// Runs work in a forked child so that a crash (signal, abort), a hang or a runaway exception
// in plugin code ends only that child: the caller gets an outcome it can report and goes on.
#pragma once

#include <sys/types.h>

#include <functional>
#include <memory>
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

// A forked child that serves requests one after another, so that many isolated calls (a
// sweep's cases) cost a round trip each instead of a process start. The child resets the
// fault signals to their default action (so a crash is a signal the parent sees), asks for
// SIGKILL when the parent dies, and answers each request with serve(request) through an
// O_CLOEXEC pipe; nothing of the child, not even an exception thrown while answering,
// returns into the caller. A crash, an exit or a hang (killed at the deadline, with the
// child's process group) ends only that child: the next ask forks a new one. The parent waits
// for a whole answer or the child's exit, not for the pipe's end, so a grandchild holding the
// pipe cannot stall it. The parent must not have started OpenMP threads (a forked child of a
// process with a live OpenMP pool can hang).
class Worker {
 public:
  using Serve = std::function<std::string(const std::string& request)>;
  // serve runs in the child, which is forked at the first ask (and again after a crash or a
  // timeout) and sees the parent's memory as it is then. options.timeout_s bounds each ask.
  Worker(Serve serve, IsolationOptions options);
  ~Worker();  // kills the child and its process group
  Worker(const Worker&) = delete;
  Worker& operator=(const Worker&) = delete;

  ChildOutcome ask(const std::string& request) { return ask(request, options_.timeout_s); }
  ChildOutcome ask(const std::string& request, double timeout_s);
  pid_t pid() const;  // the child serving now; 0 when none runs

 private:
  struct Child;
  bool start(ChildOutcome& failed);  // forks the child; false (failed says why) if it cannot
  void stop();
  Serve serve_;
  IsolationOptions options_;
  std::unique_ptr<Child> child_;
};

// work() once in a child of its own (a Worker asked once).
ChildOutcome run_isolated(const std::function<std::string()>& work,
                          const IsolationOptions& options);

// "5 s", "0.2 s": a duration as the messages above write it.
std::string format_seconds(double seconds);

}  // namespace clothlab::process
