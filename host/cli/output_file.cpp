#include "output_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <clothlab/host/errors.hpp>
#include <cstring>
#include <fstream>
#include <system_error>

namespace fs = std::filesystem;

namespace clothlab::cli {

void write_file_atomically(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  // Hidden, per-process name in the target's folder, so the rename cannot cross devices.
  std::string temporary_name(".");
  temporary_name += path.filename().string();
  temporary_name += ".tmp." + std::to_string(getpid());
  const fs::path temporary = path.parent_path() / temporary_name;
  const auto fail = [&](const std::string& why) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    return host::InputError("cannot write " + path.string() + ": " + why);
  };
  {
    std::ofstream stream(temporary, std::ios::binary | std::ios::trunc);
    if (!stream) throw fail(std::strerror(errno));
    try {
      write(stream);
    } catch (...) {
      // The target stays as it was; no half-written temporary is left behind.
      std::error_code ignored;
      fs::remove(temporary, ignored);
      throw;
    }
    stream.flush();
    if (!stream) throw fail("write failed");
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) throw fail(error.message());
}

void check_output_folder(const fs::path& path) {
  const fs::path folder = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  std::error_code error;
  if (!fs::is_directory(folder, error))
    throw host::InputError("cannot write " + path.string() + ": folder " + folder.string() +
                           " does not exist");
}

}  // namespace clothlab::cli
