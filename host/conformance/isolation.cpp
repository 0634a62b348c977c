#include "isolation.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string>

namespace clothlab::conformance {
namespace {

double monotonic_seconds() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

std::string format_seconds(double seconds) {
  std::ostringstream out;
  out << seconds << " s";
  return out.str();
}

void write_all(int fd, const std::string& bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    written += static_cast<size_t>(n);
  }
}

// Child side: one byte pass/fail followed by the reason.
[[noreturn]] void run_child(const std::function<Verdict()>& body, int fd) {
  // Fault signals kill the child, so the parent sees the signal even when a sanitizer
  // runtime installed handlers that would turn it into an exit status.
  for (int fault : {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT}) signal(fault, SIG_DFL);
  const Verdict verdict = run_guarded(body);
  write_all(fd, std::string(verdict.passed ? "P" : "F") + verdict.reason);
  close(fd);
  _exit(0);
}

// Reads everything the child writes until EOF or the deadline; false on timeout.
bool read_until_eof(int fd, double deadline, std::string& bytes) {
  char buffer[4096];
  for (;;) {
    const double left = deadline - monotonic_seconds();
    if (left <= 0) return false;
    pollfd request{fd, POLLIN, 0};
    const int ready = poll(&request, 1, static_cast<int>(std::ceil(left * 1000.0)));
    if (ready < 0 && errno == EINTR) continue;
    if (ready == 0) return false;
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    bytes.append(buffer, static_cast<size_t>(n));
  }
}

std::string describe_death(int status) {
  if (WIFSIGNALED(status)) {
    const int signal_number = WTERMSIG(status);
    const char* name = sigabbrev_np(signal_number);
    return "crashed: signal " + std::to_string(signal_number) +
           (name != nullptr ? std::string(" (SIG") + name + ")" : std::string());
  }
  return "crashed: exited with status " + std::to_string(WEXITSTATUS(status)) + " before reporting";
}

}  // namespace

Verdict run_guarded(const std::function<Verdict()>& body) {
  try {
    return body();
  } catch (const CheckFailure& failure) {
    return {false, failure.what()};
  } catch (const std::exception& e) {
    return {false, std::string("exception escaped: ") + e.what()};
  } catch (...) {
    return {false, "exception of unknown type escaped"};
  }
}

Verdict run_isolated(const std::function<Verdict()>& body, double timeout_s) {
  std::fflush(nullptr);  // so the child cannot flush the parent's pending output twice
  int fds[2];
  if (pipe(fds) != 0) return {false, std::string("runner: pipe failed: ") + strerror(errno)};
  const pid_t child = fork();
  if (child < 0) {
    close(fds[0]);
    close(fds[1]);
    return {false, std::string("runner: fork failed: ") + strerror(errno)};
  }
  if (child == 0) {
    close(fds[0]);
    run_child(body, fds[1]);
  }
  close(fds[1]);
  std::string bytes;
  const bool finished = read_until_eof(fds[0], monotonic_seconds() + timeout_s, bytes);
  close(fds[0]);
  if (!finished) kill(child, SIGKILL);
  int status = 0;
  while (waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (!finished) return {false, "timed out after " + format_seconds(timeout_s)};
  const bool clean_exit = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!clean_exit || bytes.empty()) return {false, describe_death(status)};
  return {bytes[0] == 'P', bytes.substr(1)};
}

}  // namespace clothlab::conformance
