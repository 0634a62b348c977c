#include "clothlab/process/isolation.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string_view>

namespace clothlab::process {
namespace {

constexpr size_t stderr_kept_bytes = 64 * 1024;
constexpr int child_could_not_answer = 125;  // exit status of a child whose answer failed

double monotonic_seconds() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

bool write_all(int fd, const char* bytes, size_t size) {
  size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, bytes + written, size - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;  // the parent is gone: nothing to tell
    written += static_cast<size_t>(n);
  }
  return true;
}

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

// A pipe end being read without blocking; fd -1 once it reached its end.
struct Reader {
  int fd = -1;
  std::string bytes;
  size_t keep = 0;   // 0: keep everything; else only the last `keep` bytes
  int forward = -1;  // also copy what arrives to this fd

  // Reads what is available now; closes at end of file.
  void drain() {
    char buffer[65536];
    while (fd >= 0) {
      const ssize_t n = ::read(fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) return;  // EAGAIN: nothing more for now
      if (n == 0) {
        ::close(fd);
        fd = -1;
        return;
      }
      if (forward >= 0) write_all(forward, buffer, static_cast<size_t>(n));
      bytes.append(buffer, static_cast<size_t>(n));
      if (keep > 0 && bytes.size() > keep) bytes.erase(0, bytes.size() - keep);
    }
  }
  ~Reader() {
    if (fd >= 0) ::close(fd);
  }
};

std::string signal_text(int signal_number) {
  const char* name = sigabbrev_np(signal_number);
  return "signal " + std::to_string(signal_number) +
         (name != nullptr ? std::string(" (SIG") + name + ")" : std::string());
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

int open_pidfd(pid_t child) {
#ifdef SYS_pidfd_open
  return static_cast<int>(::syscall(SYS_pidfd_open, child, 0));
#else
  (void)child;
  return -1;
#endif
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
  Reader answer{answer_pipe[0], {}, 0, -1};
  Reader error_text{error_pipe[0], {}, stderr_kept_bytes, STDERR_FILENO};
  for (const Reader* reader : {&answer, &error_text})
    if (reader->fd >= 0) ::fcntl(reader->fd, F_SETFL, O_NONBLOCK);
  const int pidfd = open_pidfd(child);

  const double deadline = monotonic_seconds() + options.timeout_s;
  int status = 0;
  bool timed_out = false;
  for (;;) {
    const pid_t reaped = ::waitpid(child, &status, WNOHANG);
    if (reaped == child) break;
    const double left = deadline - monotonic_seconds();
    if (left <= 0) {
      timed_out = true;
      ::kill(-child, SIGKILL);
      ::kill(child, SIGKILL);
      while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    pollfd watched[3] = {{answer.fd, POLLIN, 0}, {error_text.fd, POLLIN, 0}, {pidfd, POLLIN, 0}};
    // Without a pidfd the child's exit is seen by polling waitpid.
    const double slice_s = pidfd >= 0 ? left : std::min(left, 0.01);
    ::poll(watched, 3, static_cast<int>(std::ceil(slice_s * 1000.0)));
    answer.drain();
    error_text.drain();
  }
  answer.drain();
  error_text.drain();
  ::kill(-child, SIGKILL);  // grandchildren end with the child
  if (options.on_child) options.on_child(0);
  if (pidfd >= 0) ::close(pidfd);
  if (timed_out) {
    ChildOutcome outcome;
    outcome.end = ChildOutcome::End::TimedOut;
    outcome.problem = "timed out after " + format_seconds(options.timeout_s);
    outcome.child_stderr = error_text.bytes;
    return outcome;
  }
  return outcome_of(status, answer.bytes, error_text.bytes);
}

}  // namespace clothlab::process
