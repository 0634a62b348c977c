#include "clothlab/process/program.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "child_supervision.hpp"

namespace clothlab::process {

using detail::close_all;

namespace {

constexpr int could_not_exec = 127;

}  // namespace

std::optional<std::filesystem::path> find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string folders = path ? path : "/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= folders.size()) {
    const std::size_t end = std::min(folders.find(':', start), folders.size());
    const std::filesystem::path candidate =
        std::filesystem::path(folders.substr(start, end - start)) / name;
    if (end > start && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    start = end + 1;
  }
  return std::nullopt;
}

ProgramOutput run_program(const std::vector<std::string>& argv, double timeout_s) {
  if (argv.empty()) throw std::invalid_argument("run_program: no program given");
  // out, err, and the exec pipe: closed by a successful exec (O_CLOEXEC), else it carries
  // the child's errno.
  int out_pipe[2] = {-1, -1}, err_pipe[2] = {-1, -1}, exec_pipe[2] = {-1, -1};
  if (::pipe2(out_pipe, O_CLOEXEC) != 0 || ::pipe2(err_pipe, O_CLOEXEC) != 0 ||
      ::pipe2(exec_pipe, O_CLOEXEC) != 0) {
    const int error = errno;
    close_all({out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1], exec_pipe[0], exec_pipe[1]});
    throw std::runtime_error(argv[0] + ": cannot run: pipe: " + std::strerror(error));
  }
  // Built before fork: the child of a threaded process may only make async-signal-safe calls.
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const pid_t parent = ::getpid();
  const pid_t child = ::fork();
  if (child < 0) {
    const int error = errno;
    close_all({out_pipe[0], out_pipe[1], err_pipe[0], err_pipe[1], exec_pipe[0], exec_pipe[1]});
    throw std::runtime_error(argv[0] + ": cannot run: fork: " + std::strerror(error));
  }
  if (child == 0) {
    ::setpgid(0, 0);
    ::prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (::getppid() != parent) ::_exit(could_not_exec);
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::dup2(err_pipe[1], STDERR_FILENO);
    ::execv(args[0], args.data());
    const int error = errno;
    detail::write_all(exec_pipe[1], reinterpret_cast<const char*>(&error), sizeof error);
    ::_exit(could_not_exec);
  }
  ::setpgid(child, child);  // also here: the child may not have run yet
  close_all({out_pipe[1], err_pipe[1], exec_pipe[1]});
  detail::Reader out(out_pipe[0]), err(err_pipe[0]), exec_error(exec_pipe[0]);
  const detail::ChildEnd end = detail::supervise(child, {&out, &err, &exec_error}, timeout_s);
  if (exec_error.bytes.size() == sizeof(int)) {
    int error = 0;
    std::memcpy(&error, exec_error.bytes.data(), sizeof error);
    throw std::runtime_error(argv[0] + ": cannot run: " + std::strerror(error));
  }
  ProgramOutput output;
  output.timed_out = end.timed_out;
  output.exit_status = !end.timed_out && WIFEXITED(end.status) ? WEXITSTATUS(end.status) : -1;
  output.out = std::move(out.bytes);
  output.err = std::move(err.bytes);
  return output;
}

}  // namespace clothlab::process
