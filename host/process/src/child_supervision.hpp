// What both kinds of child process share (isolation.cpp runs our own code in a forked
// child, program.cpp executes another program): reading the child's pipes without
// blocking, and waiting for its exit under a deadline that kills its process group.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

namespace clothlab::process::detail {

double monotonic_seconds();

// Closes each fd that is not -1.
void close_all(std::initializer_list<int> fds);

// Writes everything, retrying on EINTR; false if the reader is gone.
bool write_all(int fd, const char* bytes, size_t size);

// A pipe end being read without blocking; fd -1 once it reached its end.
struct Reader {
  int fd = -1;
  std::string bytes;
  size_t keep = 0;   // 0: keep everything; else only the last `keep` bytes
  int forward = -1;  // also copy what arrives to this fd

  Reader(int fd_in, size_t keep_in = 0, int forward_in = -1);
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;
  ~Reader();
  // Reads what is available now; closes at end of file.
  void drain();
};

struct ChildEnd {
  int status = 0;  // as waitpid reports it
  bool timed_out = false;
  bool running = false;  // finished() held first: the child goes on (a worker between requests)
};

// Reads the pipes while waiting for the child (the leader of its own process group) to exit,
// or for finished() (when given) to hold after a read; past timeout_s kills the group. It
// waits for the exit, not for the pipes' end, so a grandchild holding a pipe cannot stall it,
// and kills the group once the child has ended (and reaped it).
ChildEnd supervise(pid_t child, const std::vector<Reader*>& readers, double timeout_s,
                   const std::function<bool()>& finished = nullptr);

// "signal 11 (SIGSEGV)"
std::string signal_text(int signal_number);

}  // namespace clothlab::process::detail
