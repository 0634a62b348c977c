#include "clothlab/process/isolation.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string_view>

#include "child_supervision.hpp"

namespace clothlab::process {
namespace {

using detail::ChildEnd;
using detail::close_all;
using detail::Reader;
using detail::signal_text;
using detail::supervise;
using detail::write_all;

constexpr size_t stderr_kept_bytes = 64 * 1024;
constexpr int child_could_not_answer = 125;  // exit status of a child whose answer failed

// A request is its size and its bytes; an answer a tag byte ('A' answer, 'E' exception
// text), its size and its bytes.
using FrameSize = uint64_t;
constexpr size_t answer_header = 1 + sizeof(FrameSize);

bool read_all(int fd, char* bytes, size_t size) {
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::read(fd, bytes + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<size_t>(n);
  }
  return true;
}

bool read_request(int fd, std::string& request) {
  FrameSize size = 0;
  if (!read_all(fd, reinterpret_cast<char*>(&size), sizeof size)) return false;
  request.resize(size);
  return read_all(fd, request.data(), request.size());
}

// MSG_NOSIGNAL: a child that died before reading is an outcome, not a SIGPIPE for the parent.
bool send_request(int fd, const std::string& request) {
  const FrameSize size = request.size();
  std::string frame(reinterpret_cast<const char*>(&size), sizeof size);
  frame += request;
  size_t sent = 0;
  while (sent < frame.size()) {
    const ssize_t n = ::send(fd, frame.data() + sent, frame.size() - sent, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    sent += static_cast<size_t>(n);
  }
  return true;
}

bool whole_answer(const std::string& bytes) {
  if (bytes.size() < answer_header) return false;
  FrameSize size = 0;
  std::memcpy(&size, bytes.data() + 1, sizeof size);
  return bytes.size() - answer_header >= size;
}

// Child side: answers requests until the parent closes its end. Nothing here may return or
// throw into the caller's code: the caller is the parent's loop, copied.
[[noreturn]] void serve_requests(int requests, int answers, const Worker::Serve& serve) noexcept {
  try {
    for (std::string request; read_request(requests, request);) {
      char tag = 'A';
      std::string bytes;
      try {
        bytes = serve(request);
      } catch (const std::exception& error) {
        tag = 'E';
        bytes = error.what();
      } catch (...) {
        tag = 'E';
        bytes = "exception of unknown type";
      }
      const FrameSize size = bytes.size();
      if (!write_all(answers, &tag, 1) ||
          !write_all(answers, reinterpret_cast<const char*>(&size), sizeof size) ||
          !write_all(answers, bytes.data(), bytes.size()))
        ::_exit(child_could_not_answer);
    }
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

ChildOutcome answered(const std::string& frame, std::string child_stderr) {
  ChildOutcome outcome;
  outcome.child_stderr = std::move(child_stderr);
  outcome.end = frame[0] == 'A' ? ChildOutcome::End::Answered : ChildOutcome::End::Threw;
  (frame[0] == 'A' ? outcome.answer : outcome.problem) = frame.substr(answer_header);
  return outcome;
}

ChildOutcome crashed(int status, std::string child_stderr) {
  ChildOutcome outcome;
  outcome.child_stderr = std::move(child_stderr);
  outcome.end = ChildOutcome::End::Crashed;
  outcome.problem = WIFSIGNALED(status)
                        ? "crashed: " + signal_text(WTERMSIG(status))
                        : "crashed: exited with status " + std::to_string(WEXITSTATUS(status)) +
                              " before reporting";
  const std::string report = sanitizer_report(outcome.child_stderr);
  if (!report.empty()) outcome.problem += ": " + report;
  return outcome;
}

ChildOutcome not_started(const char* call) {
  ChildOutcome outcome;
  outcome.end = ChildOutcome::End::Crashed;
  outcome.problem =
      std::string("cannot start a child process: ") + call + ": " + std::strerror(errno);
  return outcome;
}

}  // namespace

std::string format_seconds(double seconds) {
  std::ostringstream text;
  text << seconds << " s";
  return text.str();
}

// The parent's side of a running child: the request socket, the answer and stderr pipes.
struct Worker::Child {
  pid_t pid = 0;
  int requests = -1;
  Reader answers;
  Reader error_text;
  bool reaped = false;  // by supervise: the pid may already name another process

  Child(pid_t pid_in, int requests_in, int answers_in, int error_in)
      : pid(pid_in),
        requests(requests_in),
        answers(answers_in),
        error_text(error_in, stderr_kept_bytes, STDERR_FILENO) {}
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  ~Child() {
    ::close(requests);
    if (reaped) return;
    ::kill(-pid, SIGKILL);
    ::kill(pid, SIGKILL);
    while (::waitpid(pid, nullptr, 0) < 0 && errno == EINTR) {
    }
  }
};

Worker::Worker(Serve serve, IsolationOptions options)
    : serve_(std::move(serve)), options_(std::move(options)) {}

Worker::~Worker() { stop(); }

pid_t Worker::pid() const { return child_ ? child_->pid : 0; }

void Worker::stop() {
  if (!child_) return;
  child_.reset();
  if (options_.on_child) options_.on_child(0);
}

bool Worker::start(ChildOutcome& failed) {
  int request_socket[2];
  int answer_pipe[2];
  int error_pipe[2] = {-1, -1};
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, request_socket) != 0) {
    failed = not_started("socketpair");
    return false;
  }
  if (::pipe2(answer_pipe, O_CLOEXEC) != 0) {
    failed = not_started("pipe");
    close_all({request_socket[0], request_socket[1]});
    return false;
  }
  if (options_.capture_stderr && ::pipe2(error_pipe, O_CLOEXEC) != 0) {
    failed = not_started("pipe");
    close_all({request_socket[0], request_socket[1], answer_pipe[0], answer_pipe[1]});
    return false;
  }
  // Buffered output would otherwise be written twice, by both processes.
  std::fflush(nullptr);
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) {
    failed = not_started("fork");
    close_all({request_socket[0], request_socket[1], answer_pipe[0], answer_pipe[1], error_pipe[0],
               error_pipe[1]});
    return false;
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
    close_all({request_socket[0], answer_pipe[0]});
    if (error_pipe[1] >= 0) {
      ::dup2(error_pipe[1], STDERR_FILENO);
      close_all({error_pipe[0], error_pipe[1]});
    }
    serve_requests(request_socket[1], answer_pipe[1], serve_);
  }
  ::setpgid(child, child);  // also here: the child may not have run yet
  close_all({request_socket[1], answer_pipe[1], error_pipe[1]});
  child_ = std::make_unique<Child>(child, request_socket[0], answer_pipe[0], error_pipe[0]);
  if (options_.on_child) options_.on_child(child);
  return true;
}

ChildOutcome Worker::ask(const std::string& request, double timeout_s) {
  // A child that ended between requests (killed from outside) is replaced, not blamed.
  if (child_ && ::waitpid(child_->pid, nullptr, WNOHANG) == child_->pid) {
    child_->reaped = true;
    stop();
  }
  ChildOutcome failed;
  if (!child_ && !start(failed)) return failed;
  Child& child = *child_;
  child.answers.bytes.clear();
  child.error_text.bytes.clear();
  // A child that cannot take the request has ended: supervise reports how.
  send_request(child.requests, request);
  const ChildEnd end = supervise(child.pid, {&child.answers, &child.error_text}, timeout_s,
                                 [&] { return whole_answer(child.answers.bytes); });
  if (end.running) return answered(child.answers.bytes, std::move(child.error_text.bytes));
  child.reaped = true;
  ChildOutcome outcome;
  if (end.timed_out) {
    outcome.end = ChildOutcome::End::TimedOut;
    outcome.problem = "timed out after " + format_seconds(timeout_s);
    outcome.child_stderr = std::move(child.error_text.bytes);
  } else if (whole_answer(child.answers.bytes)) {
    outcome = answered(child.answers.bytes, std::move(child.error_text.bytes));
  } else {
    outcome = crashed(end.status, std::move(child.error_text.bytes));
  }
  stop();
  return outcome;
}

ChildOutcome run_isolated(const std::function<std::string()>& work,
                          const IsolationOptions& options) {
  Worker worker([&](const std::string&) { return work(); }, options);
  return worker.ask({});
}

}  // namespace clothlab::process
