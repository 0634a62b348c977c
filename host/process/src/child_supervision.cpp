#include "child_supervision.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>

namespace clothlab::process::detail {

namespace {

int open_pidfd(pid_t child) {
#ifdef SYS_pidfd_open
  return static_cast<int>(::syscall(SYS_pidfd_open, child, 0));
#else
  (void)child;
  return -1;
#endif
}

}  // namespace

double monotonic_seconds() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

void close_all(std::initializer_list<int> fds) {
  for (int fd : fds)
    if (fd >= 0) ::close(fd);
}

bool write_all(int fd, const char* bytes, size_t size) {
  size_t written = 0;
  while (written < size) {
    const ssize_t n = ::write(fd, bytes + written, size - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    written += static_cast<size_t>(n);
  }
  return true;
}

Reader::Reader(int fd_in, size_t keep_in, int forward_in)
    : fd(fd_in), keep(keep_in), forward(forward_in) {
  if (fd >= 0) ::fcntl(fd, F_SETFL, O_NONBLOCK);
}

Reader::~Reader() {
  if (fd >= 0) ::close(fd);
}

void Reader::drain() {
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

ChildEnd supervise(pid_t child, const std::vector<Reader*>& readers, double timeout_s,
                   const std::function<bool()>& finished) {
  const int pidfd = open_pidfd(child);
  const double deadline = monotonic_seconds() + timeout_s;
  ChildEnd end;
  std::vector<pollfd> watched(readers.size() + 1);
  for (;;) {
    if (finished && finished()) {
      end.running = true;
      if (pidfd >= 0) ::close(pidfd);
      return end;
    }
    if (::waitpid(child, &end.status, WNOHANG) == child) break;
    const double left = deadline - monotonic_seconds();
    if (left <= 0) {
      end.timed_out = true;
      ::kill(-child, SIGKILL);
      ::kill(child, SIGKILL);
      while (::waitpid(child, &end.status, 0) < 0 && errno == EINTR) {
      }
      break;
    }
    for (size_t i = 0; i < readers.size(); ++i) watched[i] = {readers[i]->fd, POLLIN, 0};
    watched.back() = {pidfd, POLLIN, 0};
    // Without a pidfd the child's exit is seen by polling waitpid.
    const double slice_s = pidfd >= 0 ? left : std::min(left, 0.01);
    ::poll(watched.data(), watched.size(), static_cast<int>(std::ceil(slice_s * 1000.0)));
    for (Reader* reader : readers) reader->drain();
  }
  for (Reader* reader : readers) reader->drain();
  ::kill(-child, SIGKILL);  // grandchildren end with the child
  if (pidfd >= 0) ::close(pidfd);
  return end;
}

std::string signal_text(int signal_number) {
  const char* name = sigabbrev_np(signal_number);
  return "signal " + std::to_string(signal_number) +
         (name != nullptr ? std::string(" (SIG") + name + ")" : std::string());
}

}  // namespace clothlab::process::detail
