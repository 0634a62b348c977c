#include "clothlab/io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <optional>
#include <random>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace clothlab::io {
namespace {

[[noreturn]] void fail(const fs::path& path, const std::string& why) {
  throw WriteError("cannot write " + path.string() + ": " + why);
}

fs::path folder_of(const fs::path& path) {
  return path.parent_path().empty() ? fs::path(".") : path.parent_path();
}

std::string temporary_prefix(const fs::path& path) {
  std::string prefix(".");
  prefix += path.filename().string();
  prefix += ".tmp-";
  return prefix;
}

const char* kind_of(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// The target's current permission bits, or none when it does not exist yet. Refuses a
// target that is not a regular file.
std::optional<mode_t> existing_mode(const fs::path& path) {
  struct stat status {};
  if (::lstat(path.c_str(), &status) != 0) {
    if (errno == ENOENT) return std::nullopt;
    fail(path, std::strerror(errno));
  }
  if (!S_ISREG(status.st_mode))
    fail(path, std::string("it is ") + kind_of(status.st_mode) +
                   "; allowed: a regular file or a new name");
  return status.st_mode & 07777;
}

// writev() of every piece, resumed after short writes and interruptions.
bool write_all(int fd, std::span<const std::string_view> pieces) {
  constexpr size_t batch = 64;  // far below IOV_MAX (1024 on Linux)
  size_t piece = 0, done = 0;   // bytes of pieces[piece] already written
  while (piece < pieces.size()) {
    iovec vectors[batch];
    size_t count = 0;
    for (size_t i = piece; i < pieces.size() && count < batch; ++i) {
      const size_t skip = i == piece ? done : 0;
      if (pieces[i].size() == skip) continue;
      vectors[count++] = {const_cast<char*>(pieces[i].data()) + skip, pieces[i].size() - skip};
    }
    if (count == 0) return true;
    const ssize_t n = ::writev(fd, vectors, static_cast<int>(count));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    auto left = static_cast<size_t>(n);
    while (piece < pieces.size() && left >= pieces[piece].size() - done) {
      left -= pieces[piece].size() - done;
      ++piece;
      done = 0;
    }
    done += left;
  }
  return true;
}

// Creates the temporary with O_EXCL at an unpredictable name; returns its fd and path.
int create_temporary(const fs::path& path, fs::path& temporary) {
  std::random_device entropy;
  std::mt19937_64 generator(entropy());
  const std::string prefix = temporary_prefix(path) + std::to_string(::getpid()) + "-";
  for (int attempt = 0; attempt < 100; ++attempt) {
    temporary = folder_of(path) / (prefix + std::to_string(generator() % 1000000000ull));
    const int fd =
        ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    if (errno != EEXIST) fail(path, std::strerror(errno));
  }
  fail(path, "no free temporary name in its folder");
}

void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // the rename happened; only its durability is unconfirmed
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

namespace {

// Removes the temporaries in folder whose writer is gone: ".NAME.tmp-PID-XXXXXX" for every
// NAME (target empty) or for target's alone.
int remove_dead_writers_temporaries(const fs::path& folder, const std::string& target) {
  const std::string prefix = target.empty() ? std::string() : "." + target + ".tmp-";
  int removed = 0;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    size_t at = 0;
    if (!prefix.empty()) {
      if (!name.starts_with(prefix)) continue;
      at = prefix.size();
    } else {
      const size_t marker = name.rfind(".tmp-");
      if (!name.starts_with('.') || marker == std::string::npos || marker == 0) continue;
      at = marker + 5;
    }
    int pid = 0;
    const char* digits = name.data() + at;
    const auto [end, problem] = std::from_chars(digits, name.data() + name.size(), pid);
    if (problem != std::errc() || *end != '-' || pid <= 0) continue;
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // its writer may still be at work
    if (fs::remove(entry.path(), error)) ++removed;
  }
  return removed;
}

}  // namespace

int remove_stale_temporaries(const fs::path& path) {
  return remove_dead_writers_temporaries(folder_of(path), path.filename().string());
}

int remove_stale_temporaries_in(const fs::path& folder) {
  return remove_dead_writers_temporaries(folder, "");
}

void check_output_path(const fs::path& path) {
  const fs::path folder = folder_of(path);
  struct stat status {};
  if (::stat(folder.c_str(), &status) != 0)
    fail(path, "folder " + folder.string() + ": " + std::strerror(errno));
  if (!S_ISDIR(status.st_mode)) fail(path, folder.string() + " is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    fail(path, "folder " + folder.string() + ": " + std::strerror(errno));
  existing_mode(path);
}

void write_file_atomically(const fs::path& path, std::string_view bytes, Durability durability,
                           StaleTemporaries stale) {
  write_file_atomically(path, std::span<const std::string_view>(&bytes, 1), durability, stale);
}

void write_file_atomically(const fs::path& path, std::span<const std::string_view> pieces,
                           Durability durability, StaleTemporaries stale) {
  const std::optional<mode_t> mode = existing_mode(path);
  if (stale == StaleTemporaries::Remove) remove_stale_temporaries(path);
  fs::path temporary;
  const int fd = create_temporary(path, temporary);
  const auto abandon = [&](const std::string& why) {
    ::close(fd);
    ::unlink(temporary.c_str());
    fail(path, why);
  };
  if (mode && ::fchmod(fd, *mode) != 0) abandon(std::strerror(errno));
  if (!write_all(fd, pieces)) abandon(std::strerror(errno));
  if (durability == Durability::Synced && ::fsync(fd) != 0) abandon(std::strerror(errno));
  if (::close(fd) != 0) {
    const int close_error = errno;
    ::unlink(temporary.c_str());
    fail(path, std::strerror(close_error));
  }
  if (::rename(temporary.c_str(), path.c_str()) != 0) {
    const int rename_error = errno;
    ::unlink(temporary.c_str());
    fail(path, std::strerror(rename_error));
  }
  if (durability == Durability::Synced) sync_folder(folder_of(path));
}

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write,
                           Durability durability, StaleTemporaries stale) {
  std::ostringstream text;
  write(text);
  if (!text) fail(path, "formatting the contents failed");
  write_file_atomically(path, text.view(), durability, stale);
}

}  // namespace clothlab::io
