// Output files appear whole or not at all, and writing one never touches anything but it:
// the bytes go to a new temporary file in the target's folder (created with O_EXCL at an
// unpredictable name, so a planted symlink cannot redirect it), are fsynced (unless the
// caller asks for Durability::Renamed), and the file is renamed over the target. A replaced file
// keeps its permission bits. A target that exists and is not a regular file (a symlink, FIFO,
// device, folder) is refused. Temporaries left by killed processes (".NAME.tmp-PID-XXXXXX" whose
// PID is gone) are removed on the next write.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string_view>

namespace clothlab::io {

// "cannot write PATH: REASON", naming the target (never the temporary file).
class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Synced: the file and its folder are fsynced, so the new file also survives a power loss.
// Renamed: no fsync; the rename is still atomic for every reader and against the writer
// being killed (whole old file or whole new one), but after an operating-system crash the
// file may be empty. For files written many times a second (frames: 4 fsyncs per frame
// would cost more than the frame).
enum class Durability { Synced, Renamed };

// Remove: a write first removes its target's temporaries left by dead writers, which scans
// the folder. Skip: for a writer of thousands of files in one folder (frames), which sweeps
// the folder once with remove_stale_temporaries_in(), so that a write costs the same however
// many files the folder holds.
enum class StaleTemporaries { Remove, Skip };

// Calls write(stream), then stores what it wrote at path atomically. Throws WriteError (and
// leaves neither a temporary nor a changed target) when it cannot; an exception from write()
// propagates the same way.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write,
                           Durability durability = Durability::Synced,
                           StaleTemporaries stale = StaleTemporaries::Remove);
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes,
                           Durability durability = Durability::Synced,
                           StaleTemporaries stale = StaleTemporaries::Remove);
// The file is the pieces one after another, handed to the kernel as they lie in memory
// (writev): no copy in between, for large binary files assembled from arrays.
void write_file_atomically(const std::filesystem::path& path,
                           std::span<const std::string_view> pieces,
                           Durability durability = Durability::Synced,
                           StaleTemporaries stale = StaleTemporaries::Remove);

// Throws WriteError unless path could be written now: its folder exists, is a folder and is
// writable, and path is absent or a regular file. Called before long work starts.
void check_output_path(const std::filesystem::path& path);

// Removes the temporaries of `path` whose writer process is gone; returns how many.
int remove_stale_temporaries(const std::filesystem::path& path);
// The same for every file in folder; returns how many.
int remove_stale_temporaries_in(const std::filesystem::path& folder);

}  // namespace clothlab::io
