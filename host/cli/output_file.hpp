// Result files appear whole or not at all: written to a temporary file in the same
// folder, then renamed over the target.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>

namespace clothlab::cli {

// Calls write(stream) on a temporary file next to path, then renames it to path.
// Throws InputError naming the file if it cannot be written; leaves no temporary file.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(std::ostream&)>& write);

// Throws InputError if path's folder does not exist, so a long run does not end in a
// write failure.
void check_output_folder(const std::filesystem::path& path);

}  // namespace clothlab::cli
