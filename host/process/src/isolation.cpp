#include "clothlab/process/isolation.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string_view>

#include "child_supervision.hpp"

namespace clothlab::process {
namespace {

using detail::ChildEnd;
using detail::Reader;
using detail::signal_text;
using detail::supervise;
using detail::write_all;

constexpr size_t stderr_kept_bytes = 64 * 1024;
constexpr int child_could_not_answer = 125;  // exit status of a child whose answer failed

// Child side: a tag byte ('A' answer, 'E' exception text) and the bytes. Nothing here may
// return or throw into the caller's code: the caller is the parent's loop, copied.
[[noreturn]] void child_main(int fd, const std::function<std::string()>& work) noexcept {
  try {
    char tag = 'A';
    std::string bytes;
    try {
      bytes = work();
    } catch (const std::exception& error) {
      tag = 'E';
      bytes = error.what();
    } catch (...) {
      tag = 'E';
      bytes = "exception of unknown type";
    }
    if (!write_all(fd, &tag, 1) || !write_all(fd, bytes.data(), bytes.size()))
      ::_exit(child_could_not_answer);
    ::close(fd);
  } catch (...) {
    ::_exit(child_could_not_answer);
  }
  // No exit handlers or static destructors: they belong to the parent.
  ::_exit(0);
}

// "==12==..." : how AddressSanitizer and LeakSanitizer begin each line of their own.
bool is_sanitizer_line(std::string_view line) {
  if (line.find(" runtime error: ") != std::string_view::npos ||
      line.starts_with("WARNING: ThreadSanitizer: "))
    return true;
  if (!line.starts_with("==")) return false;
  const size_t digits_end = line.find_first_not_of("0123456789", 2);
  return digits_end > 2 && digits_end != std::string_view::npos &&
         line.substr(digits_end).starts_with("==");
}

// A sanitizer's first line ("==12==ERROR: AddressSanitizer: heap-buffer-overflow on address
// ...", "x.cpp:3:5: runtime error: ...", "==12==ASan runtime does not come first ...") and its
// last "SUMMARY: ..." line, each when there is one.
std::string sanitizer_report(const std::string& text) {
  std::string first, summary;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (first.empty() && is_sanitizer_line(line)) first = line;
    if (line.starts_with("SUMMARY: ")) summary = line;
  }
  if (first.empty() || summary.empty()) return first + summary;
  return first + "; " + summary;
}

ChildOutcome outcome_of(int status, const std::string& answer, const std::string& child_stderr) {
  ChildOutcome outcome;
  outcome.child_stderr = child_stderr;
  const bool clean_exit = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (clean_exit && !answer.empty() && (answer[0] == 'A' || answer[0] == 'E')) {
    outcome.end = answer[0] == 'A' ? ChildOutcome::End::Answered : ChildOutcome::End::Threw;
    (answer[0] == 'A' ? outcome.answer : outcome.problem) = answer.substr(1);
    return outcome;
  }
  outcome.end = ChildOutcome::End::Crashed;
  outcome.problem = WIFSIGNALED(status)
                        ? "crashed: " + signal_text(WTERMSIG(status))
                        : "crashed: exited with status " + std::to_string(WEXITSTATUS(status)) +
                              " before reporting";
  const std::string report = sanitizer_report(child_stderr);
  if (!report.empty()) outcome.problem += ": " + report;
  return outcome;
}

}  // namespace

std::string format_seconds(double seconds) {
  std::ostringstream text;
  text << seconds << " s";
  return text.str();
}

ChildOutcome run_isolated(const std::function<std::string()>& work,
                          const IsolationOptions& options) {
  int answer_pipe[2];
  int error_pipe[2] = {-1, -1};
  ChildOutcome failed;
  failed.end = ChildOutcome::End::Crashed;
  if (::pipe2(answer_pipe, O_CLOEXEC) != 0) {
    failed.problem = std::string("cannot start a child process: pipe: ") + std::strerror(errno);
    return failed;
  }
  if (options.capture_stderr && ::pipe2(error_pipe, O_CLOEXEC) != 0) {
    failed.problem = std::string("cannot start a child process: pipe: ") + std::strerror(errno);
    ::close(answer_pipe[0]);
    ::close(answer_pipe[1]);
    return failed;
  }
  // Buffered output would otherwise be written twice, by both processes.
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) {
    failed.problem = std::string("cannot start a child process: fork: ") + std::strerror(errno);
    for (int fd : {answer_pipe[0], answer_pipe[1], error_pipe[0], error_pipe[1]})
      if (fd >= 0) ::close(fd);
    return failed;
  }
  if (child == 0) {
    // Its own process group, so a timeout also ends whatever the child started.
    ::setpgid(0, 0);
    // A child whose parent was killed (Ctrl-C on a sweep) must not run on alone.
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(child_could_not_answer);
    // Fault signals kill the child, so the parent sees the signal even when a sanitizer
    // runtime installed handlers that would turn it into an exit status.
    for (int fault : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGTRAP})
      std::signal(fault, SIG_DFL);
    ::close(answer_pipe[0]);
    if (error_pipe[1] >= 0) {
      ::dup2(error_pipe[1], STDERR_FILENO);
      ::close(error_pipe[0]);
      ::close(error_pipe[1]);
    }
    child_main(answer_pipe[1], work);
  }
  ::setpgid(child, child);  // also here: the child may not have run yet
  if (options.on_child) options.on_child(child);
  ::close(answer_pipe[1]);
  if (error_pipe[1] >= 0) ::close(error_pipe[1]);
  Reader answer(answer_pipe[0]);
  Reader error_text(error_pipe[0], stderr_kept_bytes, STDERR_FILENO);
  const ChildEnd end = supervise(child, {&answer, &error_text}, options.timeout_s);
  if (options.on_child) options.on_child(0);
  if (end.timed_out) {
    ChildOutcome outcome;
    outcome.end = ChildOutcome::End::TimedOut;
    outcome.problem = "timed out after " + format_seconds(options.timeout_s);
    outcome.child_stderr = error_text.bytes;
    return outcome;
  }
  return outcome_of(end.status, answer.bytes, error_text.bytes);
}

}  // namespace clothlab::process
